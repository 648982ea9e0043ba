/* Inversion by the Dixon matrix: exact two-row resultant, exact root isolation, polish and
 * distance test (Theorem 4.1, Remarks 2-3). */
#include "ssi/inversion.h"

#include <math.h>
#include <stdlib.h>

#include <flint/fmpz_mpoly.h>
#include <flint/fmpz_vec.h>

#include "ssi/dixon_internal.h"
#include "ssi/roots.h"

void cb_inversion_params_default(cb_inversion_params *par)
{
    par->dist_tol = 1e-6;
    par->param_tol = 1e-9;
}

void cb_inversion_init(cb_inversion_t res)
{
    res->n = res->alloc = 0;
    res->pt = NULL;
    res->inside = 0;
}

void cb_inversion_clear(cb_inversion_t res)
{
    flint_free(res->pt);
    cb_inversion_init(res);
}

/* Real roots of p (non-zero) as doubles, each isolated exactly in [-B, B] with B a power of two
 * above Fujiwara's bound 2 max |a_i / a_d|^(1 / (d - i)), then refined to width 2^-56. The
 * exact midpoints go to mids (if non-NULL, initialised here; the caller clears *n of them).
 * Returns the number of roots; out and mids are allocated here. */
static slong real_roots(double **out, fmpq **mids, const fmpz_poly_t p)
{
    slong d = fmpz_poly_degree(p);
    *out = NULL;
    if (mids)
        *mids = NULL;
    if (d < 1)
        return 0;
    slong xl;
    double ml = fmpz_get_d_2exp(&xl, fmpz_poly_lead(p));
    double lead = (double)xl + log2(fabs(ml)), lb = 0.0;
    for (slong i = 0; i < d; i++) {
        if (fmpz_is_zero(p->coeffs + i))
            continue;
        slong x;
        double mi = fmpz_get_d_2exp(&x, p->coeffs + i);
        lb = FLINT_MAX(lb, ((double)x + log2(fabs(mi)) - lead) / (double)(d - i));
    }
    fmpq_t a, b, w;
    fmpq_init(a);
    fmpq_init(b);
    fmpq_init(w);
    fmpz_one_2exp(fmpq_numref(b), (ulong)ceil(lb) + 2);
    fmpq_neg(a, b);
    fmpz_one(fmpq_numref(w));
    fmpz_one_2exp(fmpq_denref(w), 56);
    cb_roots_t r;
    cb_roots_init(r);
    slong n = 0;
    if (cb_roots_isolate(r, p, a, b, NULL) == CB_OK && r->n > 0) {
        n = r->n;
        *out = flint_malloc((size_t)n * sizeof(double));
        if (mids)
            *mids = flint_malloc((size_t)n * sizeof(fmpq));
        for (slong k = 0; k < n; k++) {
            cb_roots_refine(r, k, w);
            (*out)[k] = cb_roots_mid_d(r, k);
            if (mids) {
                fmpq_init(*mids + k);
                fmpq_add(*mids + k, r->root[k].lo, r->root[k].hi);
                fmpq_div_2exp(*mids + k, *mids + k, 1);
            }
        }
    }
    cb_roots_clear(r);
    fmpq_clear(a);
    fmpq_clear(b);
    fmpq_clear(w);
    return n;
}

/* |P(u, v) - X| after at most 12 Gauss-Newton steps from (u, v), each kept only if it lowers the
 * distance. */
static double polish(double *u, double *v, const cb_dixon_patch_t P, const double X[3])
{
    double h[3][4], p[3];
    double best = HUGE_VAL;
    for (int it = 0; it <= 12; it++) {
        _cb_dixon_patch_eval_h(h, P, *u, *v);
        double wgt = h[0][3], r[3], J[3][2], d2 = 0.0;
        for (int q = 0; q < 3; q++) {
            p[q] = h[0][q] / wgt;
            r[q] = X[q] - p[q];
            d2 += r[q] * r[q];
            J[q][0] = (h[1][q] - p[q] * h[1][3]) / wgt;
            J[q][1] = (h[2][q] - p[q] * h[2][3]) / wgt;
        }
        double dist = sqrt(d2);
        if (!(dist < best))
            break;
        best = dist;
        if (it == 12)
            break;
        double a = 0, b = 0, c = 0, g0 = 0, g1 = 0;
        for (int q = 0; q < 3; q++) {
            a += J[q][0] * J[q][0];
            b += J[q][0] * J[q][1];
            c += J[q][1] * J[q][1];
            g0 += J[q][0] * r[q];
            g1 += J[q][1] * r[q];
        }
        double det = a * c - b * b;
        if (!(fabs(det) > 0.0) || !isfinite(det))
            break;
        double du = (c * g0 - b * g1) / det, dv = (a * g1 - b * g0) / det;
        double nu = *u + du, nv = *v + dv;
        _cb_dixon_patch_eval_h(h, P, nu, nv);
        double nd2 = 0.0;
        for (int q = 0; q < 3; q++) {
            double e = X[q] - h[0][q] / h[0][3];
            nd2 += e * e;
        }
        if (!(sqrt(nd2) < best))
            break;
        *u = nu;
        *v = nv;
    }
    return best;
}

static void push(cb_inversion_t res, double u, double v, double dist, double tol_u,
                 double tol_v)
{
    for (slong k = 0; k < res->n; k++) {
        cb_inversion_point *q = res->pt + k;
        if (fabs(q->u - u) <= tol_u && fabs(q->v - v) <= tol_v) {
            if (dist < q->dist) {
                q->u = u;
                q->v = v;
                q->dist = dist;
            }
            return;
        }
    }
    if (res->n == res->alloc) {
        res->alloc = res->alloc ? 2 * res->alloc : 4;
        res->pt = flint_realloc(res->pt, (size_t)res->alloc * sizeof *res->pt);
    }
    cb_inversion_point *q = res->pt + res->n++;
    q->u = u;
    q->v = v;
    q->dist = dist;
    q->inside = 0;
}

static int cmp_point(const void *a, const void *b)
{
    const cb_inversion_point *p = a, *q = b;
    if (p->u != q->u)
        return p->u < q->u ? -1 : 1;
    return (p->v > q->v) - (p->v < q->v);
}

/* Res_v of the two rows as polynomials a_k(u) + b_k(u) v (n = 2: bidegree (2m - 1, 1)), the
 * 2 x 2 Sylvester determinant b_0 a_1 - a_0 b_1, without the general multivariate resultant
 * (its setup was a quarter of an inversion). 0 when a row has no v term, whose resultant is
 * not that determinant. */
static int two_row_linear(fmpz_poly_t R, fmpz *const row[2], slong m)
{
    fmpz_poly_t a[2], b[2];
    for (int k = 0; k < 2; k++) {
        fmpz_poly_init(a[k]);
        fmpz_poly_init(b[k]);
        for (slong i = 0; i < 2 * m; i++) {
            fmpz_poly_set_coeff_fmpz(a[k], i, row[k] + 2 * i);
            fmpz_poly_set_coeff_fmpz(b[k], i, row[k] + 2 * i + 1);
        }
    }
    int ok = !fmpz_poly_is_zero(b[0]) && !fmpz_poly_is_zero(b[1]);
    if (ok) {
        fmpz_poly_t t;
        fmpz_poly_init(t);
        fmpz_poly_mul(R, b[0], a[1]);
        fmpz_poly_mul(t, a[0], b[1]);
        fmpz_poly_sub(R, R, t);
        fmpz_poly_clear(t);
    }
    for (int k = 0; k < 2; k++) {
        fmpz_poly_clear(a[k]);
        fmpz_poly_clear(b[k]);
    }
    return ok;
}

/* The polynomial in u of two random row combinations of M (Res_v, or the row itself when
 * n = 1); zero if unlucky or if M has rank <= 1. */
static void row_resultant(fmpz_poly_t R, const fmpz_mat_t M, slong m, slong n, flint_rand_t st)
{
    slong s = M->r;
    fmpz *row[2] = {_fmpz_vec_init(s), _fmpz_vec_init(s)};
    fmpz_t lam;
    fmpz_init(lam);
    for (int k = 0; k < 2; k++)
        for (slong i = 0; i < s; i++) {
            fmpz_set_si(lam, (slong)n_randint(st, UWORD(1) << 17) - (WORD(1) << 16));
            _fmpz_vec_scalar_addmul_fmpz(row[k], M->rows[i], s, lam);
        }
    fmpz_clear(lam);
    fmpz_poly_zero(R);
    if (n == 1) {
        for (slong k = 0; k < 2 * m; k++)
            fmpz_poly_set_coeff_fmpz(R, k, row[0] + k);
    } else if (n != 2 || !two_row_linear(R, row, m)) {
        fmpz_mpoly_ctx_t ctx;
        fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
        fmpz_mpoly_t p[2], res;
        ulong e[2];
        for (int k = 0; k < 2; k++) {
            fmpz_mpoly_init(p[k], ctx);
            for (slong i = 0; i < 2 * m; i++)
                for (slong j = 0; j < n; j++) {
                    e[0] = (ulong)i;
                    e[1] = (ulong)j;
                    fmpz_mpoly_set_coeff_fmpz_ui(p[k], row[k] + i * n + j, e, ctx);
                }
        }
        fmpz_mpoly_init(res, ctx);
        if (fmpz_mpoly_resultant(res, p[0], p[1], 1, ctx))
            fmpz_mpoly_get_fmpz_poly(R, res, 0, ctx);
        fmpz_mpoly_clear(res, ctx);
        for (int k = 0; k < 2; k++)
            fmpz_mpoly_clear(p[k], ctx);
        fmpz_mpoly_ctx_clear(ctx);
    }
    for (int k = 0; k < 2; k++)
        _fmpz_vec_clear(row[k], s);
}

/* rho(v) = sum_q lam_q (d X_q - P_q w) at u = num / den, cleared of denominators: the random
 * moving plane through X at that u, whose real roots hold the v of every preimage. */
static void moving_plane_at(fmpz_poly_t rho, const cb_dixon_patch_t P, const fmpz *Xi,
                            const fmpz *lam, const fmpq_t u)
{
    slong m = P->m, n = P->n, len = _cb_dixon_patch_len(P);
    const fmpz *d = P->coef + 3 * len;
    fmpz_t e, t, pw;
    fmpz_init(e);
    fmpz_init(t);
    fmpz_init(pw);
    fmpz_poly_zero(rho);
    for (slong j = 0; j <= n; j++) {
        fmpz_zero(t);
        for (slong i = 0; i <= m; i++) {
            slong k = i * (n + 1) + j;
            fmpz_zero(e);
            for (int q = 0; q < 3; q++) {
                fmpz_t c;
                fmpz_init(c);
                fmpz_mul(c, d + k, Xi + q);
                fmpz_submul(c, P->coef + q * len + k, Xi + 3);
                fmpz_addmul(e, lam + q, c);
                fmpz_clear(c);
            }
            /* e num^i den^(m-i) */
            fmpz_pow_ui(pw, fmpq_numref(u), (ulong)i);
            fmpz_mul(e, e, pw);
            fmpz_pow_ui(pw, fmpq_denref(u), (ulong)(m - i));
            fmpz_mul(e, e, pw);
            fmpz_add(t, t, e);
        }
        fmpz_poly_set_coeff_fmpz(rho, j, t);
    }
    fmpz_clear(e);
    fmpz_clear(t);
    fmpz_clear(pw);
}

cb_status cb_inversion_solve(cb_inversion_t res, const cb_dixon_pencil_t D,
                             const cb_dixon_patch_t P, const double X[3],
                             const cb_inversion_params *par, cb_error *err)
{
    for (int q = 0; q < 3; q++)
        if (!isfinite(X[q]))
            return cb_error_set(err, CB_ERR_INVALID, "point coordinate %d is not finite", q);
    if (!(par->dist_tol >= 0.0) || !(par->param_tol >= 0.0) || !isfinite(par->dist_tol) ||
        !isfinite(par->param_tol))
        return cb_error_set(err, CB_ERR_INVALID, "tolerances must be finite and >= 0 (dist_tol "
                            "%g, param_tol %g)", par->dist_tol, par->param_tol);
    slong m = P->m, n = P->n, s = D->size;

    /* X exactly, as the homogeneous integer point Xi = X 2^-e (w = 2^-e). */
    double Xh[4] = {X[0], X[1], X[2], 1.0};
    fmpz *Xi = _fmpz_vec_init(4);
    _cb_dyadic_to_fmpz(Xi, Xh, 4);
    fmpz_mat_t M;
    fmpz_mat_init(M, s, s);
    for (int q = 0; q < 4; q++)
        for (slong i = 0; i < s; i++)
            _fmpz_vec_scalar_addmul_fmpz(M->rows[i], D->D[q]->rows[i], s, Xi + q);

    flint_rand_t st;
    flint_randinit(st);
    flint_randseed(st, CB_DIXON_SEED, CB_DIXON_SEED ^ 0x1b87u);
    fmpz_poly_t R, rho;
    fmpz_poly_init(R);
    fmpz_poly_init(rho);
    for (int attempt = 0; attempt < 4 && fmpz_poly_is_zero(R); attempt++)
        row_resultant(R, M, m, n, st);
    fmpz_mat_clear(M);
    cb_status ret = CB_OK;
    res->n = 0;
    res->inside = 0;
    if (fmpz_poly_is_zero(R)) {
        ret = cb_error_set(err, CB_ERR_NUMERIC, "D(X) at (%g, %g, %g) gives a zero resultant "
                           "for four random row pairs (rank <= 1)", X[0], X[1], X[2]);
    } else {
        fmpz lam[3];
        for (int q = 0; q < 3; q++) {
            fmpz_init(lam + q);
            fmpz_set_si(lam + q, (slong)n_randint(st, UWORD(1) << 17) - (WORD(1) << 16));
        }
        double *us;
        fmpq *umid;
        slong nu = real_roots(&us, &umid, R);
        double su = P->box[1] - P->box[0], sv = P->box[3] - P->box[2];
        for (slong a = 0; a < nu; a++) {
            moving_plane_at(rho, P, Xi, lam, umid + a);
            double *vs;
            slong nv = fmpz_poly_is_zero(rho) ? 0 : real_roots(&vs, NULL, rho);
            for (slong b = 0; b < nv; b++) {
                double u = us[a], v = vs[b];
                double dist = polish(&u, &v, P, X);
                if (dist <= par->dist_tol)
                    push(res, u, v, dist, par->param_tol * su, par->param_tol * sv);
            }
            if (nv > 0)
                flint_free(vs);
            fmpq_clear(umid + a);
        }
        if (nu > 0) {
            flint_free(us);
            flint_free(umid);
        }
        for (int q = 0; q < 3; q++)
            fmpz_clear(lam + q);
    }
    for (slong k = 0; k < res->n; k++) {
        cb_inversion_point *q = res->pt + k;
        double tu = par->param_tol * (P->box[1] - P->box[0]);
        double tv = par->param_tol * (P->box[3] - P->box[2]);
        q->inside = q->u >= P->box[0] - tu && q->u <= P->box[1] + tu &&
                    q->v >= P->box[2] - tv && q->v <= P->box[3] + tv;
        res->inside |= q->inside;
        cb_dixon_patch_to_domain(&q->u, &q->v, P, q->u, q->v);
    }
    if (res->n > 1)
        qsort(res->pt, (size_t)res->n, sizeof *res->pt, cmp_point);
    fmpz_poly_clear(R);
    fmpz_poly_clear(rho);
    flint_randclear(st);
    _fmpz_vec_clear(Xi, 4);
    return ret;
}
