/* Exact integer patches and the Dixon pencil of their moving planes. */
#include "ssi/dixon.h"

#include <math.h>
#include <stdlib.h>

#include "ssi/dixon_internal.h"

/* ---------------------------------------------------------------- exact scaling ------------ */

slong _cb_dyadic_to_fmpz(fmpz *out, const double *x, slong n)
{
    slong *ex = flint_malloc((size_t)FLINT_MAX(n, 1) * sizeof *ex);
    slong emin = WORD_MAX;
    for (slong i = 0; i < n; i++) {
        int e;
        double f = frexp(x[i], &e);
        slong mant = (slong)ldexp(f, 53); /* exact: f has at most 53 significant bits */
        ex[i] = (slong)e - 53;
        if (mant == 0)
            continue;
        while ((mant & 1) == 0) {
            mant /= 2;
            ex[i]++;
        }
        fmpz_set_si(out + i, mant);
        emin = FLINT_MIN(emin, ex[i]);
    }
    if (emin == WORD_MAX)
        emin = 0;
    for (slong i = 0; i < n; i++) {
        if (x[i] == 0.0)
            fmpz_zero(out + i);
        else
            fmpz_mul_2exp(out + i, out + i, (ulong)(ex[i] - emin));
    }
    flint_free(ex);
    return emin;
}

slong _cb_fmpz_vec_get_d_scaled(double *out, const fmpz *v, slong n)
{
    slong e = 0;
    for (slong i = 0; i < n; i++)
        e = FLINT_MAX(e, (slong)fmpz_bits(v + i));
    for (slong i = 0; i < n; i++) {
        slong x;
        double m = fmpz_get_d_2exp(&x, v + i);
        out[i] = fmpz_is_zero(v + i) ? 0.0 : ldexp(m, (int)(x - e));
    }
    return e;
}

/* ---------------------------------------------------------------- patches ------------------ */

void cb_dixon_patch_init(cb_dixon_patch_t P)
{
    P->m = P->n = 0;
    P->coef = NULL;
    P->cd = NULL;
    for (int i = 0; i < 4; i++)
        P->box[i] = P->domain[i] = 0.0;
}

void cb_dixon_patch_clear(cb_dixon_patch_t P)
{
    if (P->coef)
        _fmpz_vec_clear(P->coef, 4 * (P->m + 1) * (P->n + 1));
    flint_free(P->cd);
    cb_dixon_patch_init(P);
}

/* Takes over coef (4 (m+1)(n+1) integers) into P, divides out their common content (the
 * surface is projective, so this changes nothing) and fills the double copy. */
static void patch_adopt(cb_dixon_patch_t P, fmpz *coef, slong m, slong n, const double box[4],
                        const double domain[4])
{
    cb_dixon_patch_clear(P);
    slong len = 4 * (m + 1) * (n + 1);
    fmpz_t g;
    fmpz_init(g);
    _fmpz_vec_content(g, coef, len);
    if (!fmpz_is_zero(g) && !fmpz_is_one(g))
        _fmpz_vec_scalar_divexact_fmpz(coef, coef, len, g);
    fmpz_clear(g);
    P->m = m;
    P->n = n;
    P->coef = coef;
    P->cd = flint_malloc((size_t)len * sizeof(double));
    _cb_fmpz_vec_get_d_scaled(P->cd, coef, len);
    for (int i = 0; i < 4; i++) {
        P->box[i] = box[i];
        P->domain[i] = domain[i];
    }
}

static cb_status check_finite(const double *x, slong n, const char *what, cb_error *err)
{
    for (slong i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return cb_error_set(err, CB_ERR_INVALID, "%s %ld is not finite", what, (long)i);
    return CB_OK;
}

cb_status cb_dixon_patch_set_bezier(cb_dixon_patch_t P, const cb_nurbs_surface_t s,
                                    cb_error *err)
{
    slong m = s->deg_u, n = s->deg_v;
    if (m < 1 || n < 1 || m > CB_MAX_DEGREE || n > CB_MAX_DEGREE)
        return cb_error_set(err, CB_ERR_INVALID, "Bezier patch of degree (%ld, %ld): degrees "
                            "must be in [1, %d]", (long)m, (long)n, CB_MAX_DEGREE);
    if (s->n_u != m + 1 || s->n_v != n + 1)
        return cb_error_set(err, CB_ERR_INVALID, "not a single Bezier patch: %d x %d control "
                            "points for degree (%ld, %ld); split it with "
                            "cb_nurbs_surface_extract_bezier", s->n_u, s->n_v, (long)m, (long)n);
    slong len = (m + 1) * (n + 1);
    cb_status st = check_finite(s->cw, 4 * len, "homogeneous control value", err);
    if (st != CB_OK)
        return st;
    double dom[4];
    cb_nurbs_surface_domain(s, dom);
    if (!(dom[0] < dom[1]) || !(dom[2] < dom[3]))
        return cb_error_set(err, CB_ERR_INVALID, "empty parameter domain [%g, %g] x [%g, %g]",
                            dom[0], dom[1], dom[2], dom[3]);

    /* Bernstein coefficients as integers, component-major. */
    double *raw = flint_malloc((size_t)(4 * len) * sizeof(double));
    for (slong i = 0; i <= m; i++)
        for (slong j = 0; j <= n; j++)
            for (int q = 0; q < 4; q++)
                raw[q * len + i * (n + 1) + j] = cb_nurbs_surface_cw(s, (int)i, (int)j)[q];
    fmpz *bern = _fmpz_vec_init(4 * len);
    _cb_dyadic_to_fmpz(bern, raw, 4 * len);
    flint_free(raw);

    /* Separable exact conversion: first along v, then along u. tv[l][j] is the coefficient of
     * v^l in B_{j,n}(v): C(n,l) C(l,j) (-1)^(l-j). */
    fmpz *tu = _fmpz_vec_init((m + 1) * (m + 1)), *tv = _fmpz_vec_init((n + 1) * (n + 1));
    fmpz_t b1, b2;
    fmpz_init(b1);
    fmpz_init(b2);
    for (int dir = 0; dir < 2; dir++) {
        slong d = dir ? n : m;
        fmpz *t = dir ? tv : tu;
        for (slong l = 0; l <= d; l++)
            for (slong j = 0; j <= l; j++) {
                fmpz_bin_uiui(b1, (ulong)d, (ulong)l);
                fmpz_bin_uiui(b2, (ulong)l, (ulong)j);
                fmpz_mul(t + l * (d + 1) + j, b1, b2);
                if ((l - j) & 1)
                    fmpz_neg(t + l * (d + 1) + j, t + l * (d + 1) + j);
            }
    }
    fmpz *mid = _fmpz_vec_init(4 * len), *coef = _fmpz_vec_init(4 * len);
    for (int q = 0; q < 4; q++) {
        const fmpz *b = bern + q * len;
        fmpz *md = mid + q * len, *c = coef + q * len;
        for (slong i = 0; i <= m; i++)
            for (slong l = 0; l <= n; l++)
                for (slong j = 0; j <= l; j++)
                    fmpz_addmul(md + i * (n + 1) + l, tv + l * (n + 1) + j, b + i * (n + 1) + j);
        for (slong k = 0; k <= m; k++)
            for (slong i = 0; i <= k; i++)
                for (slong l = 0; l <= n; l++)
                    fmpz_addmul(c + k * (n + 1) + l, tu + k * (m + 1) + i, md + i * (n + 1) + l);
    }
    fmpz_clear(b1);
    fmpz_clear(b2);
    _fmpz_vec_clear(tu, (m + 1) * (m + 1));
    _fmpz_vec_clear(tv, (n + 1) * (n + 1));
    _fmpz_vec_clear(mid, 4 * len);
    _fmpz_vec_clear(bern, 4 * len);
    const double unit[4] = {0.0, 1.0, 0.0, 1.0};
    patch_adopt(P, coef, m, n, unit, dom);
    return CB_OK;
}

cb_status cb_dixon_patch_set_power(cb_dixon_patch_t P, slong m, slong n, const double *hc,
                                   const double box[4], cb_error *err)
{
    if (m < 1 || n < 1 || m > CB_MAX_DEGREE || n > CB_MAX_DEGREE)
        return cb_error_set(err, CB_ERR_INVALID, "bidegree (%ld, %ld): degrees must be in "
                            "[1, %d]", (long)m, (long)n, CB_MAX_DEGREE);
    slong len = (m + 1) * (n + 1);
    cb_status st = check_finite(hc, 4 * len, "coefficient", err);
    if (st == CB_OK)
        st = check_finite(box, 4, "box value", err);
    if (st != CB_OK)
        return st;
    if (!(box[0] < box[1]) || !(box[2] < box[3]))
        return cb_error_set(err, CB_ERR_INVALID, "empty parameter box [%g, %g] x [%g, %g]",
                            box[0], box[1], box[2], box[3]);
    int dzero = 1;
    for (slong i = 0; i < len; i++)
        dzero = dzero && hc[3 * len + i] == 0.0;
    if (dzero)
        return cb_error_set(err, CB_ERR_INVALID, "weight polynomial d is identically zero");
    fmpz *coef = _fmpz_vec_init(4 * len);
    _cb_dyadic_to_fmpz(coef, hc, 4 * len);
    patch_adopt(P, coef, m, n, box, box);
    return CB_OK;
}

/* Horner in v inside Horner in u for the four components at once. */
double cb_dixon_patch_eval(double p[3], const cb_dixon_patch_t P, double u, double v)
{
    double h[3][4];
    _cb_dixon_patch_eval_h(h, P, u, v);
    for (int q = 0; q < 3; q++)
        p[q] = h[0][q] / h[0][3];
    return h[0][3];
}

void _cb_dixon_patch_eval_h(double h[3][4], const cb_dixon_patch_t P, double u, double v)
{
    slong m = P->m, n = P->n, len = _cb_dixon_patch_len(P);
    for (int q = 0; q < 4; q++) {
        const double *c = P->cd + q * len;
        double f = 0, fu = 0, fv = 0;
        for (slong i = m; i >= 0; i--) {
            double r = 0, rv = 0;
            for (slong j = n; j >= 0; j--) {
                rv = rv * v + r;
                r = r * v + c[i * (n + 1) + j];
            }
            fu = fu * u + f;
            f = f * u + r;
            fv = fv * u + rv;
        }
        h[0][q] = f;
        h[1][q] = fu;
        h[2][q] = fv;
    }
}

void cb_dixon_patch_to_domain(double *du, double *dv, const cb_dixon_patch_t P, double u,
                              double v)
{
    const double *b = P->box, *d = P->domain;
    *du = d[0] + (u - b[0]) * ((d[1] - d[0]) / (b[1] - b[0]));
    *dv = d[2] + (v - b[2]) * ((d[3] - d[2]) / (b[3] - b[2]));
}

void _cb_dixon_patch_reduce(ulong *cp, const cb_dixon_patch_t P, nmod_t mod)
{
    _fmpz_vec_get_nmod_vec(cp, P->coef, 4 * _cb_dixon_patch_len(P), mod);
}

void _cb_dixon_patch_eval_nmod(ulong out[4], const ulong *cp, slong m, slong n, ulong u,
                               ulong v, nmod_t mod)
{
    slong len = (m + 1) * (n + 1);
    for (int q = 0; q < 4; q++) {
        const ulong *c = cp + q * len;
        ulong f = 0;
        for (slong i = m; i >= 0; i--) {
            ulong r = 0;
            for (slong j = n; j >= 0; j--)
                r = nmod_add(nmod_mul(r, v, mod), c[i * (n + 1) + j], mod);
            f = nmod_add(nmod_mul(f, u, mod), r, mod);
        }
        out[q] = f;
    }
}

void _cb_dixon_patch_eval_grid_nmod(ulong *out, const ulong *cp, slong m, slong n, slong du,
                                    slong dv, nmod_t mod)
{
    slong len = (m + 1) * (n + 1), w = dv + 1;
    ulong *col = flint_malloc((size_t)(m + 1) * sizeof(ulong));
    for (int q = 0; q < 4; q++) {
        const ulong *c = cp + q * len;
        ulong *o = out + q * (du + 1) * w;
        for (slong j = 0; j <= dv; j++) {
            ulong v = nmod_set_ui((ulong)j, mod);
            for (slong i = 0; i <= m; i++) {
                ulong r = 0;
                for (slong k = n; k >= 0; k--)
                    r = nmod_add(nmod_mul(r, v, mod), c[i * (n + 1) + k], mod);
                col[i] = r;
            }
            for (slong i = 0; i <= du; i++) {
                ulong u = nmod_set_ui((ulong)i, mod), f = 0;
                for (slong k = m; k >= 0; k--)
                    f = nmod_add(nmod_mul(f, u, mod), col[k], mod);
                o[i * w + j] = f;
            }
        }
    }
    flint_free(col);
}

/* ---------------------------------------------------------------- Dixon matrix ------------- */

/* Dense integer polynomial in (u, v, alpha, beta) with sz[k] coefficients per variable. */
typedef struct {
    slong sz[4];
    fmpz *c;
} poly4;

static void poly4_init(poly4 *p, slong su, slong sv, slong sa, slong sb)
{
    p->sz[0] = su;
    p->sz[1] = sv;
    p->sz[2] = sa;
    p->sz[3] = sb;
    p->c = _fmpz_vec_init(su * sv * sa * sb);
}

static slong poly4_len(const poly4 *p)
{
    return p->sz[0] * p->sz[1] * p->sz[2] * p->sz[3];
}

static void poly4_clear(poly4 *p)
{
    _fmpz_vec_clear(p->c, poly4_len(p));
}

static fmpz *poly4_at(const poly4 *p, slong i, slong j, slong k, slong l)
{
    return p->c + ((i * p->sz[1] + j) * p->sz[2] + k) * p->sz[3] + l;
}

/* out += sign a b; out must be large enough for every product exponent. */
static void poly4_addmul(poly4 *out, const poly4 *a, const poly4 *b, int sign)
{
    for (slong i = 0; i < a->sz[0]; i++)
        for (slong j = 0; j < a->sz[1]; j++)
            for (slong k = 0; k < a->sz[2]; k++)
                for (slong l = 0; l < a->sz[3]; l++) {
                    const fmpz *x = poly4_at(a, i, j, k, l);
                    if (fmpz_is_zero(x))
                        continue;
                    for (slong i2 = 0; i2 < b->sz[0]; i2++)
                        for (slong j2 = 0; j2 < b->sz[1]; j2++)
                            for (slong k2 = 0; k2 < b->sz[2]; k2++)
                                for (slong l2 = 0; l2 < b->sz[3]; l2++) {
                                    const fmpz *y = poly4_at(b, i2, j2, k2, l2);
                                    fmpz *z = poly4_at(out, i + i2, j + j2, k + k2, l + l2);
                                    if (sign > 0)
                                        fmpz_addmul(z, x, y);
                                    else
                                        fmpz_submul(z, x, y);
                                }
                }
}

void cb_dixon_matrix(fmpz_mat_t out, const fmpz *f, const fmpz *g, const fmpz *h, slong m,
                     slong n)
{
    const fmpz *F[3] = {f, g, h};
    poly4 A[3], R[3], B[3], C[3], delta;
    for (int q = 0; q < 3; q++) {
        const fmpz *p = F[q];
        /* (v^j - beta^j) / (v - beta) = sum_{a+b=j-1} v^a beta^b */
        poly4_init(&A[q], m + 1, n, 1, n);
        for (slong i = 0; i <= m; i++)
            for (slong a = 0; a < n; a++)
                for (slong b = 0; a + b + 1 <= n; b++)
                    fmpz_set(poly4_at(&A[q], i, a, 0, b), p + i * (n + 1) + a + b + 1);
        poly4_init(&R[q], m + 1, 1, 1, n + 1);
        for (slong i = 0; i <= m; i++)
            for (slong j = 0; j <= n; j++)
                fmpz_set(poly4_at(&R[q], i, 0, 0, j), p + i * (n + 1) + j);
        /* (u^i - alpha^i) / (u - alpha) = sum_{c+d=i-1} u^c alpha^d */
        poly4_init(&B[q], m, 1, m, n + 1);
        for (slong c = 0; c < m; c++)
            for (slong d = 0; c + d + 1 <= m; d++)
                for (slong j = 0; j <= n; j++)
                    fmpz_set(poly4_at(&B[q], c, 0, d, j), p + (c + d + 1) * (n + 1) + j);
    }
    /* C = R x B, then delta = -A . C. */
    for (int q = 0; q < 3; q++) {
        int q1 = (q + 1) % 3, q2 = (q + 2) % 3;
        poly4_init(&C[q], 2 * m, 1, m, 2 * n + 1);
        poly4_addmul(&C[q], &R[q1], &B[q2], 1);
        poly4_addmul(&C[q], &R[q2], &B[q1], -1);
    }
    poly4_init(&delta, 3 * m, n, m, 3 * n);
    for (int q = 0; q < 3; q++)
        poly4_addmul(&delta, &A[q], &C[q], -1);

    /* The terms of u-degree >= 2m and beta-degree >= 2n cancel in the sum (primer §2). */
    slong size = 2 * m * n;
    fmpz_mat_clear(out);
    fmpz_mat_init(out, size, size);
    for (slong i = 0; i < m; i++)
        for (slong j = 0; j < 2 * n; j++)
            for (slong k = 0; k < 2 * m; k++)
                for (slong l = 0; l < n; l++)
                    fmpz_set(fmpz_mat_entry(out, i * 2 * n + j, k * n + l),
                             poly4_at(&delta, k, l, i, j));
    for (int q = 0; q < 3; q++) {
        poly4_clear(&A[q]);
        poly4_clear(&R[q]);
        poly4_clear(&B[q]);
        poly4_clear(&C[q]);
    }
    poly4_clear(&delta);
}

/* ---------------------------------------------------------------- pencil ------------------- */

void cb_dixon_pencil_init(cb_dixon_pencil_t D)
{
    D->m = D->n = D->size = 0;
    for (int q = 0; q < 4; q++)
        fmpz_mat_init(D->D[q], 0, 0);
    D->Dd = NULL;
    D->dexp = 0;
}

void cb_dixon_pencil_clear(cb_dixon_pencil_t D)
{
    for (int q = 0; q < 4; q++)
        fmpz_mat_clear(D->D[q]);
    flint_free(D->Dd);
    D->Dd = NULL;
}

/* Rank of (P, P_u, P_v) (homogeneous, 4 x 3) at a random point modulo a random prime. */
static slong jacobian_rank_nmod(const cb_dixon_patch_t P, flint_rand_t st)
{
    nmod_t mod;
    nmod_init(&mod, n_randprime(st, 62, 1));
    slong m = P->m, n = P->n, len = _cb_dixon_patch_len(P);
    ulong *cp = flint_malloc((size_t)(4 * len) * sizeof(ulong));
    _cb_dixon_patch_reduce(cp, P, mod);
    ulong u = n_randint(st, mod.n), v = n_randint(st, mod.n);
    nmod_mat_t J;
    nmod_mat_init(J, 4, 3, mod.n);
    /* Partial derivatives from the power coefficients: d/du u^i v^j = i u^(i-1) v^j. */
    for (int q = 0; q < 4; q++) {
        const ulong *c = cp + q * len;
        ulong val = 0, du = 0, dv = 0, ui = 1;
        for (slong i = 0; i <= m; i++) {
            ulong vj = 1, r = 0, rv = 0, vjm = 0; /* vjm = v^(j-1) */
            for (slong j = 0; j <= n; j++) {
                r = nmod_add(r, nmod_mul(c[i * (n + 1) + j], vj, mod), mod);
                if (j > 0)
                    rv = nmod_add(rv, nmod_mul(nmod_mul(c[i * (n + 1) + j], (ulong)j, mod),
                                               vjm, mod), mod);
                vjm = vj;
                vj = nmod_mul(vj, v, mod);
            }
            val = nmod_add(val, nmod_mul(r, ui, mod), mod);
            dv = nmod_add(dv, nmod_mul(rv, ui, mod), mod);
            ui = nmod_mul(ui, u, mod);
        }
        ulong uim = 1; /* u^(i-1) */
        for (slong i = 1; i <= m; i++) {
            ulong vj = 1, r = 0;
            for (slong j = 0; j <= n; j++) {
                r = nmod_add(r, nmod_mul(c[i * (n + 1) + j], vj, mod), mod);
                vj = nmod_mul(vj, v, mod);
            }
            du = nmod_add(du, nmod_mul(nmod_mul(r, (ulong)i, mod), uim, mod), mod);
            uim = nmod_mul(uim, u, mod);
        }
        nmod_mat_entry(J, q, 0) = val;
        nmod_mat_entry(J, q, 1) = du;
        nmod_mat_entry(J, q, 2) = dv;
    }
    slong r = nmod_mat_rank(J);
    nmod_mat_clear(J);
    flint_free(cp);
    return r;
}

cb_status cb_dixon_pencil_set(cb_dixon_pencil_t D, const cb_dixon_patch_t P, cb_error *err)
{
    slong m = P->m, n = P->n, len = _cb_dixon_patch_len(P);
    flint_rand_t st;
    flint_randinit(st);
    flint_randseed(st, CB_DIXON_SEED, CB_DIXON_SEED ^ 0x9e37u);
    slong jr = FLINT_MAX(jacobian_rank_nmod(P, st), jacobian_rank_nmod(P, st));
    flint_randclear(st);
    if (jr < 3)
        return cb_error_set(err, CB_ERR_INVALID, "degenerate patch: it collapses to a %s "
                            "(the Jacobian of the homogeneous map has rank %ld < 3 at random "
                            "points), so it has no implicit equation", jr <= 1 ? "point" : "curve",
                            (long)jr);
    fmpz_mat_t C;
    fmpz_mat_init(C, 4, len);
    for (int q = 0; q < 4; q++)
        for (slong i = 0; i < len; i++)
            fmpz_set(fmpz_mat_entry(C, q, i), P->coef + q * len + i);
    slong cr = fmpz_mat_rank(C);
    fmpz_mat_clear(C);
    if (cr < 4)
        return cb_error_set(err, CB_ERR_UNSUPPORTED, "planar patch: all control points lie on "
                            "one plane, where the Dixon matrix vanishes identically (no "
                            "implicit equation but a power of the plane, no inversion); "
                            "intersect with the plane as an analytic surface instead");

    const fmpz *a = P->coef, *b = a + len, *c = b + len, *d = c + len;
    D->m = m;
    D->n = n;
    D->size = 2 * m * n;
    cb_dixon_matrix(D->D[0], d, b, c, m, n);
    cb_dixon_matrix(D->D[1], a, d, c, m, n);
    cb_dixon_matrix(D->D[2], a, b, d, m, n);
    cb_dixon_matrix(D->D[3], a, b, c, m, n);
    fmpz_mat_neg(D->D[3], D->D[3]);

    slong s2 = D->size * D->size;
    fmpz *all = _fmpz_vec_init(4 * s2);
    for (int q = 0; q < 4; q++)
        for (slong i = 0; i < D->size; i++)
            _fmpz_vec_set(all + q * s2 + i * D->size, D->D[q]->rows[i], D->size);
    flint_free(D->Dd);
    D->Dd = flint_malloc((size_t)(4 * s2) * sizeof(double));
    D->dexp = _cb_fmpz_vec_get_d_scaled(D->Dd, all, 4 * s2);
    _fmpz_vec_clear(all, 4 * s2);
    return CB_OK;
}

void _cb_dixon_pencil_reduce(ulong *Dp, const cb_dixon_pencil_t D, nmod_t mod)
{
    slong s = D->size;
    for (int q = 0; q < 4; q++)
        for (slong i = 0; i < s; i++)
            _fmpz_vec_get_nmod_vec(Dp + q * s * s + i * s, D->D[q]->rows[i], s, mod);
}

void _cb_dixon_pencil_eval_nmod(nmod_mat_t M, const ulong *Dp, slong size, const ulong X[4],
                                nmod_t mod)
{
    slong s2 = size * size;
    for (slong i = 0; i < size; i++)
        for (slong j = 0; j < size; j++) {
            slong k = i * size + j;
            ulong acc = nmod_mul(X[0], Dp[k], mod);
            acc = nmod_add(acc, nmod_mul(X[1], Dp[s2 + k], mod), mod);
            acc = nmod_add(acc, nmod_mul(X[2], Dp[2 * s2 + k], mod), mod);
            acc = nmod_add(acc, nmod_mul(X[3], Dp[3 * s2 + k], mod), mod);
            nmod_mat_entry(M, i, j) = acc;
        }
}

slong _cb_nmod_mat_pivots(slong *rows, slong *cols, nmod_mat_t A)
{
    slong nr = A->r, nc = A->c;
    nmod_t mod = A->mod;
    slong *rp = flint_malloc((size_t)FLINT_MAX(nr, 1) * sizeof(slong));
    slong *cpm = flint_malloc((size_t)FLINT_MAX(nc, 1) * sizeof(slong));
    for (slong i = 0; i < nr; i++)
        rp[i] = i;
    for (slong j = 0; j < nc; j++)
        cpm[j] = j;
    slong r = 0;
    for (; r < FLINT_MIN(nr, nc); r++) {
        slong pi = -1, pj = -1;
        for (slong i = r; i < nr && pi < 0; i++)
            for (slong j = r; j < nc; j++)
                if (nmod_mat_entry(A, i, j) != 0) {
                    pi = i;
                    pj = j;
                    break;
                }
        if (pi < 0)
            break;
        if (pi != r) {
            ulong *t = A->rows[pi];
            A->rows[pi] = A->rows[r];
            A->rows[r] = t;
            slong ti = rp[pi];
            rp[pi] = rp[r];
            rp[r] = ti;
        }
        if (pj != r) {
            for (slong i = 0; i < nr; i++) {
                ulong t = nmod_mat_entry(A, i, pj);
                nmod_mat_entry(A, i, pj) = nmod_mat_entry(A, i, r);
                nmod_mat_entry(A, i, r) = t;
            }
            slong tj = cpm[pj];
            cpm[pj] = cpm[r];
            cpm[r] = tj;
        }
        ulong inv = n_invmod(nmod_mat_entry(A, r, r), mod.n);
        for (slong i = r + 1; i < nr; i++) {
            ulong f = nmod_mul(nmod_mat_entry(A, i, r), inv, mod);
            if (f == 0)
                continue;
            for (slong j = r; j < nc; j++)
                nmod_mat_entry(A, i, j) = nmod_sub(nmod_mat_entry(A, i, j),
                                                   nmod_mul(f, nmod_mat_entry(A, r, j), mod),
                                                   mod);
        }
    }
    for (slong k = 0; k < r; k++) {
        rows[k] = rp[k];
        cols[k] = cpm[k];
    }
    flint_free(rp);
    flint_free(cpm);
    return r;
}

slong cb_dixon_pencil_rank(const cb_dixon_pencil_t D)
{
    slong s = D->size, best = 0;
    flint_rand_t st;
    flint_randinit(st);
    flint_randseed(st, CB_DIXON_SEED, CB_DIXON_SEED ^ 0x2545u);
    ulong *Dp = flint_malloc((size_t)(4 * s * s) * sizeof(ulong));
    for (int trial = 0; trial < 2; trial++) {
        nmod_t mod;
        nmod_init(&mod, n_randprime(st, 62, 1));
        _cb_dixon_pencil_reduce(Dp, D, mod);
        ulong X[4];
        for (int q = 0; q < 4; q++)
            X[q] = n_randint(st, mod.n);
        nmod_mat_t M;
        nmod_mat_init(M, s, s, mod.n);
        _cb_dixon_pencil_eval_nmod(M, Dp, s, X, mod);
        best = FLINT_MAX(best, nmod_mat_rank(M));
        nmod_mat_clear(M);
    }
    flint_free(Dp);
    flint_randclear(st);
    return best;
}

slong cb_dixon_rank_d(double *A, slong rows, slong cols, double rel_tol)
{
    slong r = 0;
    double first = 0.0;
    for (; r < FLINT_MIN(rows, cols); r++) {
        slong pi = r, pj = r;
        double best = -1.0;
        for (slong i = r; i < rows; i++)
            for (slong j = r; j < cols; j++)
                if (fabs(A[i * cols + j]) > best) {
                    best = fabs(A[i * cols + j]);
                    pi = i;
                    pj = j;
                }
        if (r == 0)
            first = best;
        if (!(best > rel_tol * first) || best == 0.0)
            break;
        for (slong j = 0; j < cols; j++) {
            double t = A[pi * cols + j];
            A[pi * cols + j] = A[r * cols + j];
            A[r * cols + j] = t;
        }
        for (slong i = 0; i < rows; i++) {
            double t = A[i * cols + pj];
            A[i * cols + pj] = A[i * cols + r];
            A[i * cols + r] = t;
        }
        for (slong i = r + 1; i < rows; i++) {
            double f = A[i * cols + r] / A[r * cols + r];
            for (slong j = r; j < cols; j++)
                A[i * cols + j] -= f * A[r * cols + j];
        }
    }
    return r;
}

void cb_dixon_pencil_eval_d(double *M, const cb_dixon_pencil_t D, const double X[3])
{
    slong s2 = D->size * D->size;
    const double *d = D->Dd;
    for (slong k = 0; k < s2; k++)
        M[k] = X[0] * d[k] + X[1] * d[s2 + k] + X[2] * d[2 * s2 + k] + d[3 * s2 + k];
}

slong cb_dixon_pencil_rank_d(const cb_dixon_pencil_t D, const double X[3], double rel_tol)
{
    double *M = flint_malloc((size_t)(D->size * D->size) * sizeof(double));
    cb_dixon_pencil_eval_d(M, D, X);
    slong r = cb_dixon_rank_d(M, D->size, D->size, rel_tol);
    flint_free(M);
    return r;
}
