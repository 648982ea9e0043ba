/* ssi_coincide.c — proofs that a patch lies on (or within tol of) the other surface, for the
 * coincidence records (ssi/ssi.h cb_ssi_coincident). Samples only choose which pairs try a
 * proof (ssi_tol.h CB_SSI_COINCIDENT_FILTER); the proofs below decide. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <arb.h>
#include <flint/fmpq.h>

#include "ssi/dixon_internal.h"
#include "ssi/spline.h"
#include "ssi/ssi.h"
#include "ssi/ssi_tol.h"

/* ---------------------------------------------------------------- implicit P --------------- */

/* In place on the d + 1 balls a[0], a[stride], ...: the coefficients of p(x + c). */
static void taylor_shift(arb_ptr a, slong stride, slong d, const arb_t c, slong prec)
{
    arb_t t;
    arb_init(t);
    for (slong i = 0; i < d; i++)
        for (slong j = d - 1; j >= i; j--) {
            arb_mul(t, a + (j + 1) * stride, c, prec);
            arb_add(a + j * stride, a + j * stride, t, prec);
        }
    arb_clear(t);
}

/* Lower bound g (>= 0) of |grad F| over the box [lo, hi] (Euclidean, w = 1): F shifted to the
 * box centre c exactly (balls), then grad G(h) = grad G(0) + R(h) with |R_k(h)| bounded by
 * sum over the terms of degree >= 2 of alpha_k |g_alpha| r^(alpha - e_k). */
static void grad_lower(arb_t g, const cb_implicit_struct *F, const double lo[3],
                       const double hi[3])
{
    slong N = F->deg, L = N + 1, prec = 96;
    slong len = cb_poly3_len((int)N);
    for (slong i = 0; i < len; i++)
        prec = FLINT_MAX(prec, 96 + (slong)fmpz_bits(F->c + i));
    /* Dense cube a[i][j][k], zero where i + j + k > N. */
    arb_ptr a = _arb_vec_init(L * L * L);
#define A(i, j, k) (a + ((i) * L + (j)) * L + (k))
    for (int i = 0; i <= N; i++)
        for (int j = 0; i + j <= N; j++)
            for (int k = 0; i + j + k <= N; k++)
                arb_set_fmpz(A(i, j, k), F->c + cb_poly3_index(i, j, k));
    double c[3], r[3];
    for (int q = 0; q < 3; q++) {
        c[q] = 0.5 * lo[q] + 0.5 * hi[q];
        /* r >= the distance of every box point from c (rounded up twice over). */
        r[q] = fmax(hi[q] - c[q], c[q] - lo[q]);
        r[q] = (r[q] + fabs(r[q]) * 0x1p-50 + 0x1p-1060) * (1 + 0x1p-50);
    }
    arb_t cx;
    arb_init(cx);
    arb_set_d(cx, c[0]);
    for (int j = 0; j <= N; j++)
        for (int k = 0; j + k <= N; k++)
            taylor_shift(A(0, j, k), L * L, N - j - k, cx, prec);
    arb_set_d(cx, c[1]);
    for (int i = 0; i <= N; i++)
        for (int k = 0; i + k <= N; k++)
            taylor_shift(A(i, 0, k), L, N - i - k, cx, prec);
    arb_set_d(cx, c[2]);
    for (int i = 0; i <= N; i++)
        for (int j = 0; i + j <= N; j++)
            taylor_shift(A(i, j, 0), 1, N - i - j, cx, prec);
    /* Remainders R_q and the gradient at the centre. */
    arb_t R[3], t, pw, g0[3];
    for (int q = 0; q < 3; q++) {
        arb_init(R[q]);
        arb_init(g0[q]);
    }
    arb_init(t);
    arb_init(pw);
    arb_set(g0[0], A(1, 0, 0));
    arb_set(g0[1], A(0, 1, 0));
    arb_set(g0[2], A(0, 0, 1));
    arb_t rr[3];
    for (int q = 0; q < 3; q++) {
        arb_init(rr[q]);
        arb_set_d(rr[q], r[q]);
    }
    for (int i = 0; i <= N; i++)
        for (int j = 0; i + j <= N; j++)
            for (int k = 0; i + j + k <= N; k++) {
                if (i + j + k < 2)
                    continue;
                int e[3] = {i, j, k};
                for (int q = 0; q < 3; q++) {
                    if (e[q] == 0)
                        continue;
                    arb_abs(t, A(i, j, k));
                    arb_mul_si(t, t, e[q], prec);
                    for (int p = 0; p < 3; p++) {
                        arb_pow_ui(pw, rr[p], (ulong)(e[p] - (p == q)), prec);
                        arb_mul(t, t, pw, prec);
                    }
                    arb_add(R[q], R[q], t, prec);
                }
            }
#undef A
    /* |grad G(h)| >= |grad G(0)| - |R| and >= |(|g0_q| - R_q)_+|: the larger. */
    arb_t n0, nr, n1;
    arb_init(n0);
    arb_init(nr);
    arb_init(n1);
    for (int q = 0; q < 3; q++) {
        arb_sqr(t, g0[q], prec);
        arb_add(n0, n0, t, prec);
        arb_sqr(t, R[q], prec);
        arb_add(nr, nr, t, prec);
        arb_abs(t, g0[q]);
        arb_sub(t, t, R[q], prec);
        arf_t lb;
        arf_init(lb);
        arb_get_lbound_arf(lb, t, prec);
        if (arf_sgn(lb) > 0) {
            arb_set_arf(t, lb);
            arb_sqr(t, t, prec);
            arb_add(n1, n1, t, prec);
        }
        arf_clear(lb);
    }
    arb_sqrt(n0, n0, prec);
    arb_sqrt(nr, nr, prec);
    arb_sub(n0, n0, nr, prec);
    arb_sqrt(n1, n1, prec);
    arf_t b0, b1;
    arf_init(b0);
    arf_init(b1);
    arb_get_lbound_arf(b0, n0, prec);
    arb_get_lbound_arf(b1, n1, prec);
    if (arf_cmp(b1, b0) > 0)
        arf_swap(b0, b1);
    if (arf_sgn(b0) <= 0 || !arf_is_finite(b0))
        arb_zero(g);
    else
        arb_set_arf(g, b0);
    arf_clear(b0);
    arf_clear(b1);
    arb_clear(n0);
    arb_clear(nr);
    arb_clear(n1);
    for (int q = 0; q < 3; q++) {
        arb_clear(R[q]);
        arb_clear(g0[q]);
        arb_clear(rr[q]);
    }
    arb_clear(t);
    arb_clear(pw);
    arb_clear(cx);
    _arb_vec_clear(a, L * L * L);
}

int _cb_ssi_coincide_implicit(double *width, const cb_implicit_struct *F, const cb_phi_struct *phi,
                              const cb_dixon_patch_struct *qd, const cb_nurbs_surface_struct *q,
                              double tol)
{
    slong N = F->deg, len = (phi->ds + 1) * (phi->dt + 1), np = q->n_u * q->n_v;
    if (N < 1 || np < 1)
        return 0;
    /* max |phi| over the patch <= the largest |Bernstein coefficient| (each rounded once from
     * the exact value, within a few ulps: 2^-40 covers them). */
    double bmax = 0;
    for (slong k = 0; k < len; k++)
        bmax = fmax(bmax, fabs(phi->bern[k]));
    /* Q's weight polynomial d = 2^e w: d(0, 0) is its constant coefficient, w(0, 0) the first
     * control weight, so min d >= d(0, 0) min_w / w_00 (the weights are d's Bernstein
     * coefficients up to 2^e, all positive). */
    double wmin = HUGE_VAL, w00 = q->cw[3];
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (slong k = 0; k < np; k++) {
        double w = q->cw[4 * k + 3];
        if (!(w > 0))
            return 0;
        wmin = fmin(wmin, w);
        for (int c = 0; c < 3; c++) {
            /* Outward: the division rounds. */
            double x = q->cw[4 * k + c] / w;
            lo[c] = fmin(lo[c], x - fabs(x) * 0x1p-51 - 0x1p-1060);
            hi[c] = fmax(hi[c], x + fabs(x) * 0x1p-51 + 0x1p-1060);
        }
    }
    const fmpz *d00 = qd->coef + 3 * _cb_dixon_patch_len(qd);
    if (fmpz_sgn(d00) <= 0)
        return 0;
    /* The gradient flow from a point of Q reaches F = 0 within width <= tol: the box grown by
     * tol (per coordinate, so it holds that ball) must bound |grad F| from below. */
    double grow = CB_SSI_COINCIDENT_WIDTH * tol;
    for (int c = 0; c < 3; c++) {
        lo[c] -= grow * (1 + 0x1p-40);
        hi[c] += grow * (1 + 0x1p-40);
    }
    arb_t M, D, G, W;
    arb_init(M);
    arb_init(D);
    arb_init(G);
    arb_init(W);
    slong prec = 128;
    arb_set_d(M, bmax);
    arb_mul_2exp_si(M, M, phi->exp);
    arb_mul_ui(M, M, (ulong)1 << 20, prec);
    arb_div_ui(M, M, ((ulong)1 << 20) - 1, prec); /* the rounding slack, upward */
    arb_set_fmpz(D, d00);
    arb_t t;
    arb_init(t);
    arb_set_d(t, wmin);
    arb_mul(D, D, t, prec);
    arb_set_d(t, w00);
    arb_div(D, D, t, prec);
    arb_clear(t);
    arb_pow_ui(D, D, (ulong)N, prec);
    grad_lower(G, F, lo, hi);
    int ok = 0;
    if (arb_is_positive(G) && arb_is_positive(D)) {
        arb_mul(G, G, D, prec);
        arb_div(W, M, G, prec);
        arf_t ub;
        arf_init(ub);
        arb_get_ubound_arf(ub, W, prec);
        double w = arf_get_d(ub, ARF_RND_UP);
        if (w <= CB_SSI_COINCIDENT_WIDTH * tol) {
            ok = 1;
            *width = w;
        }
        arf_clear(ub);
    }
    arb_clear(M);
    arb_clear(D);
    arb_clear(G);
    arb_clear(W);
    return ok;
}

/* ---------------------------------------------------------------- P's continued patch ------ */

/* Distance from X to P's map continued over local parameters [-1, 2]^2 (de Casteljau holds
 * outside [0, 1]^2 too, and stays on P's algebraic surface), and the parameters uv of the
 * nearest point found: the nearest of a 13 x 13 grid, or uv when warm, then Gauss-Newton (at
 * most 30 steps, each kept only when it gets closer). An upper bound on the distance. */
static double bez_project(double uv[2], const _cb_ssi_bez *P, const double X[3], int warm)
{
    double A[3], Au[3], Av[3], best = HUGE_VAL;
    if (!warm)
        for (int i = 0; i <= 12; i++)
            for (int j = 0; j <= 12; j++) {
                double u = -1 + i / 4.0, v = -1 + j / 4.0;
                _cb_ssi_bez_eval(A, Au, Av, P, u, v);
                double e = (A[0] - X[0]) * (A[0] - X[0]) + (A[1] - X[1]) * (A[1] - X[1]) +
                           (A[2] - X[2]) * (A[2] - X[2]);
                if (e < best) {
                    best = e;
                    uv[0] = u;
                    uv[1] = v;
                }
            }
    _cb_ssi_bez_eval(A, Au, Av, P, uv[0], uv[1]);
    best = (A[0] - X[0]) * (A[0] - X[0]) + (A[1] - X[1]) * (A[1] - X[1]) +
           (A[2] - X[2]) * (A[2] - X[2]);
    for (int it = 0; it < 30 && best > 0; it++) {
        double a = 0, b = 0, cc = 0, ru = 0, rv = 0;
        for (int k = 0; k < 3; k++) {
            double r = X[k] - A[k];
            a += Au[k] * Au[k];
            b += Au[k] * Av[k];
            cc += Av[k] * Av[k];
            ru += Au[k] * r;
            rv += Av[k] * r;
        }
        double det = a * cc - b * b;
        if (!(fabs(det) > 0) || !isfinite(det))
            break;
        double nu = fmin(2, fmax(-1, uv[0] + (cc * ru - b * rv) / det));
        double nv = fmin(2, fmax(-1, uv[1] + (a * rv - b * ru) / det));
        double B[3], Bu[3], Bv[3];
        _cb_ssi_bez_eval(B, Bu, Bv, P, nu, nv);
        double e = (B[0] - X[0]) * (B[0] - X[0]) + (B[1] - X[1]) * (B[1] - X[1]) +
                   (B[2] - X[2]) * (B[2] - X[2]);
        if (!(e < best))
            break;
        best = e;
        uv[0] = nu;
        uv[1] = nv;
        memcpy(A, B, sizeof A);
        memcpy(Au, Bu, sizeof Au);
        memcpy(Av, Bv, sizeof Av);
    }
    return sqrt(best);
}

int _cb_ssi_coincide_filter_bez(const _cb_ssi_bez *P, const _cb_ssi_bez *Q, double tol)
{
    double uvp[2] = {0.5, 0.5};
    const int n = CB_SSI_COINCIDENT_GRID, n2 = n * n;
    for (int k = 0; k < n2; k++) {
        int g = (k + n2 / 2) % n2; /* the centre first: a pair far apart costs one point */
        double X[3], Xu[3], Xv[3];
        _cb_ssi_bez_eval(X, Xu, Xv, Q, (double)(g / n) / (n - 1), (double)(g % n) / (n - 1));
        if (!(bez_project(uvp, P, X, k > 0) <= CB_SSI_COINCIDENT_FILTER * tol))
            return 0;
    }
    return 1;
}

/* ---------------------------------------------------------------- exact reparameterisation - */

/* The double x as the exact rational it is. */
void _cb_fmpq_set_d(fmpq_t q, double x)
{
    if (x == 0) {
        fmpq_zero(q);
        return;
    }
    int e;
    double f = frexp(x, &e); /* x = f 2^e, |f| in [1/2, 1): f 2^53 is an integer */
    fmpz_t m;
    fmpz_init(m);
    fmpz_set_d(m, ldexp(f, 53));
    fmpz_set(fmpq_numref(q), m);
    fmpz_one(fmpq_denref(q));
    slong k = (slong)e - 53;
    if (k >= 0)
        fmpq_mul_2exp(q, q, (ulong)k);
    else
        fmpq_div_2exp(q, q, (ulong)(-k));
    fmpz_clear(m);
}

/* A tensor Bernstein polynomial with fmpq coefficients of dim components, bidegree (a, b):
 * c[(i (b + 1) + j) dim + q]. */
typedef struct {
    int a, b, dim;
    fmpq *c;
} qbern;

static void qb_init(qbern *p, int a, int b, int dim)
{
    p->a = a;
    p->b = b;
    p->dim = dim;
    p->c = _fmpq_vec_init((slong)(a + 1) * (b + 1) * dim);
}

static void qb_clear(qbern *p) { _fmpq_vec_clear(p->c, (slong)(p->a + 1) * (p->b + 1) * p->dim); }

#define QB(p, i, j, q) ((p)->c + ((slong)(i) * ((p)->b + 1) + (j)) * (p)->dim + (q))

/* The Bezier curve with d + 1 control values c[k stride] (fmpq) restricted to [x0, x1] (its
 * parameter, any rationals): the blossoms B(x0^(d-i), x1^i), in place. */
static void qcurve_reparam(fmpq *c, slong stride, int d, const fmpq_t x0, const fmpq_t x1)
{
    fmpq *b = _fmpq_vec_init(d + 1), *out = _fmpq_vec_init(d + 1);
    fmpq_t one_m, t;
    fmpq_init(one_m);
    fmpq_init(t);
    for (int i = 0; i <= d; i++) {
        for (int k = 0; k <= d; k++)
            fmpq_set(b + k, c + k * stride);
        for (int r = 1; r <= d; r++) {
            const fmpq *x = r <= d - i ? x0 : x1;
            fmpq_one(one_m);
            fmpq_sub(one_m, one_m, x);
            for (int k = 0; k + r <= d; k++) {
                fmpq_mul(t, b + k + 1, x);
                fmpq_mul(b + k, b + k, one_m);
                fmpq_add(b + k, b + k, t);
            }
        }
        fmpq_set(out + i, b);
    }
    for (int i = 0; i <= d; i++)
        fmpq_set(c + i * stride, out + i);
    fmpq_clear(one_m);
    fmpq_clear(t);
    _fmpq_vec_clear(b, d + 1);
    _fmpq_vec_clear(out, d + 1);
}

/* out += sg f[fq] g[gq] as Bernstein polynomials (component oq of out, bidegree the sums). */
static void qb_mul_acc(qbern *out, int oq, const qbern *f, int fq, const qbern *g, int gq, int sg,
                       const fmpz *bin, int bw)
{
    fmpq_t t;
    fmpq_init(t);
#define BIN(n, k) (bin + (n) * bw + (k))
    for (int i = 0; i <= f->a; i++)
        for (int j = 0; j <= f->b; j++)
            for (int k = 0; k <= g->a; k++)
                for (int l = 0; l <= g->b; l++) {
                    fmpq_mul(t, QB(f, i, j, fq), QB(g, k, l, gq));
                    if (fmpq_is_zero(t))
                        continue;
                    fmpz_t num, den;
                    fmpz_init(num);
                    fmpz_init(den);
                    fmpz_mul(num, BIN(f->a, i), BIN(g->a, k));
                    fmpz_mul(num, num, BIN(f->b, j));
                    fmpz_mul(num, num, BIN(g->b, l));
                    fmpz_mul(den, BIN(f->a + g->a, i + k), BIN(f->b + g->b, j + l));
                    fmpq_mul_fmpz(t, t, num);
                    fmpq_div_fmpz(t, t, den);
                    if (sg > 0)
                        fmpq_add(QB(out, i + k, j + l, oq), QB(out, i + k, j + l, oq), t);
                    else
                        fmpq_sub(QB(out, i + k, j + l, oq), QB(out, i + k, j + l, oq), t);
                    fmpz_clear(num);
                    fmpz_clear(den);
                }
#undef BIN
    fmpq_clear(t);
}

/* Homogeneous net of a Bezier patch (w x, w y, w z, w) as fmpq, bidegree (deg_u, deg_v). */
static void qb_from_patch(qbern *p, const cb_nurbs_surface_struct *s)
{
    qb_init(p, s->deg_u, s->deg_v, 4);
    for (int i = 0; i <= s->deg_u; i++)
        for (int j = 0; j <= s->deg_v; j++)
            for (int q = 0; q < 4; q++)
                _cb_fmpq_set_d(QB(p, i, j, q), s->cw[4 * (i * s->n_v + j) + q]);
}

/* The least Bernstein coefficient of component q. */
static void qb_min(fmpq_t m, const qbern *p, int q)
{
    fmpq_set(m, QB(p, 0, 0, q));
    for (int i = 0; i <= p->a; i++)
        for (int j = 0; j <= p->b; j++)
            if (fmpq_cmp(QB(p, i, j, q), m) < 0)
                fmpq_set(m, QB(p, i, j, q));
}

/* Candidate A: p's local box [u0, u1] x [v0, v1] mapped from q's (s, t) (swap: u follows t).
 * Returns 1 exact, 2 within tol (*width), 0 neither. */
static int check_reparam(double *width, const cb_nurbs_surface_struct *p,
                         const cb_nurbs_surface_struct *q, const fmpq *box, int swap, double tol)
{
    qbern P, Q;
    qb_from_patch(&P, p);
    qb_from_patch(&Q, q);
    for (int j = 0; j <= P.b; j++)
        for (int c = 0; c < 4; c++)
            qcurve_reparam(QB(&P, 0, j, c), (slong)(P.b + 1) * 4, P.a, box + 0, box + 1);
    for (int i = 0; i <= P.a; i++)
        for (int c = 0; c < 4; c++)
            qcurve_reparam(QB(&P, i, 0, c), 4, P.b, box + 2, box + 3);
    /* In q's order: (s, t) outer, inner. */
    qbern R;
    if (swap) {
        qb_init(&R, P.b, P.a, 4);
        for (int i = 0; i <= P.a; i++)
            for (int j = 0; j <= P.b; j++)
                for (int c = 0; c < 4; c++)
                    fmpq_set(QB(&R, j, i, c), QB(&P, i, j, c));
        qb_clear(&P);
        P = R;
    }
    int ok = 0;
    fmpq_t mp, mq;
    fmpq_init(mp);
    fmpq_init(mq);
    qb_min(mp, &P, 3);
    qb_min(mq, &Q, 3);
    if (fmpq_sgn(mp) > 0 && fmpq_sgn(mq) > 0) {
        int A = P.a + Q.a, B = P.b + Q.b, bw = FLINT_MAX(A, B) + 1;
        fmpz *bin = _fmpz_vec_init(bw * bw);
        for (int n = 0; n < bw; n++)
            for (int k = 0; k <= n; k++)
                fmpz_bin_uiui(bin + n * bw + k, (ulong)n, (ulong)k);
        /* D = P(A) w_q - q w_P(A): zero iff the same points; |D| / (w_P w_q) the distance. */
        qbern D;
        qb_init(&D, A, B, 3);
        for (int c = 0; c < 3; c++) {
            qb_mul_acc(&D, c, &P, c, &Q, 3, 1, bin, bw);
            qb_mul_acc(&D, c, &Q, c, &P, 3, -1, bin, bw);
        }
        fmpq_t n2, mx, t;
        fmpq_init(n2);
        fmpq_init(mx);
        fmpq_init(t);
        for (int i = 0; i <= A; i++)
            for (int j = 0; j <= B; j++) {
                fmpq_zero(n2);
                for (int c = 0; c < 3; c++) {
                    fmpq_mul(t, QB(&D, i, j, c), QB(&D, i, j, c));
                    fmpq_add(n2, n2, t);
                }
                if (fmpq_cmp(n2, mx) > 0)
                    fmpq_set(mx, n2);
            }
        if (fmpq_is_zero(mx)) {
            ok = 1;
            *width = 0;
        } else {
            /* max |D|^2 <= (tol min w_P min w_q)^2, exactly. */
            _cb_fmpq_set_d(t, CB_SSI_COINCIDENT_WIDTH * tol);
            fmpq_mul(t, t, mp);
            fmpq_mul(t, t, mq);
            fmpq_mul(t, t, t);
            if (fmpq_cmp(mx, t) <= 0) {
                ok = 2;
                double w = sqrt(fmpq_get_d(mx)) / (fmpq_get_d(mp) * fmpq_get_d(mq));
                *width = w * (1 + 0x1p-40);
            }
        }
        fmpq_clear(n2);
        fmpq_clear(mx);
        fmpq_clear(t);
        qb_clear(&D);
        _fmpz_vec_clear(bin, bw * bw);
    }
    fmpq_clear(mp);
    fmpq_clear(mq);
    qb_clear(&P);
    qb_clear(&Q);
    return ok;
}

/* x snapped to the nearest multiple of 2^-30 when that is within 2^-40 of it. */
static double snap(double x)
{
    double y = ldexp(nearbyint(ldexp(x, 30)), -30);
    return fabs(y - x) <= 0x1p-40 ? y : x;
}

int _cb_ssi_coincide_reparam(double *width, const cb_nurbs_surface_struct *p,
                             const cb_nurbs_surface_struct *q, const _cb_ssi_bez *P,
                             const _cb_ssi_bez *Q, double tol)
{
    fmpq box[4];
    for (int k = 0; k < 4; k++)
        fmpq_init(box + k);
    int best = 0;
    double bw = HUGE_VAL, w;
    /* 1. The same parameterisation: q's domain in p's local coordinates. */
    double pd[4], qd[4];
    cb_nurbs_surface_domain(p, pd);
    cb_nurbs_surface_domain(q, qd);
    if (pd[1] > pd[0] && pd[3] > pd[2]) {
        fmpq_t a, w0;
        fmpq_init(a);
        fmpq_init(w0);
        for (int k = 0; k < 4; k++) {
            int d = k / 2;
            _cb_fmpq_set_d(box + k, qd[k]);
            _cb_fmpq_set_d(a, pd[2 * d]);
            fmpq_sub(box + k, box + k, a);
            _cb_fmpq_set_d(w0, pd[2 * d + 1]);
            fmpq_sub(w0, w0, a);
            fmpq_div(box + k, box + k, w0);
        }
        fmpq_clear(a);
        fmpq_clear(w0);
        int r = check_reparam(&w, p, q, box, 0, tol);
        if (r == 1)
            best = 1;
        else if (r == 2 && w < bw) {
            best = 2;
            bw = w;
        }
    }
    /* 2. Through p's parameters of q's corners (projection on p continued). */
    if (best != 1) {
        double c[3][2], X[3], Xu[3], Xv[3];
        double st[3][2] = {{0, 0}, {1, 0}, {0, 1}};
        int found = 1;
        for (int k = 0; k < 3 && found; k++) {
            _cb_ssi_bez_eval(X, Xu, Xv, Q, st[k][0], st[k][1]);
            found = bez_project(c[k], P, X, 0) <= CB_SSI_COINCIDENT_FILTER * tol;
        }
        if (found) {
            double du = c[1][0] - c[0][0], dv = c[1][1] - c[0][1];
            int swap = fabs(dv) > fabs(du);
            double b[4] = {c[0][0], swap ? c[2][0] : c[1][0], c[0][1], swap ? c[1][1] : c[2][1]};
            for (int pass = 0; pass < 2 && best != 1; pass++) {
                for (int k = 0; k < 4; k++)
                    _cb_fmpq_set_d(box + k, pass == 0 ? snap(b[k]) : b[k]);
                if (fmpq_equal(box + 0, box + 1) || fmpq_equal(box + 2, box + 3))
                    continue;
                int r = check_reparam(&w, p, q, box, swap, tol);
                if (r == 1)
                    best = 1;
                else if (r == 2 && w < bw) {
                    best = 2;
                    bw = w;
                }
            }
        }
    }
    for (int k = 0; k < 4; k++)
        fmpq_clear(box + k);
    if (best == 1)
        *width = 0;
    else if (best == 2)
        *width = bw;
    return best;
}
