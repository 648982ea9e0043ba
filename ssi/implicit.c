/* Implicit equations: Dixon determinant or minor by modular interpolation and CRT, extraneous
 * factors removed by factorisation, the exact vanishing proof, analytic equations. */
#include "ssi/implicit.h"

#include <math.h>

#include <flint/fmpz_mat.h>
#include <flint/fmpz_mpoly_factor.h>
#include <flint/fmpz_vec.h>

#include "ssi/dixon_internal.h"

#include "ssi/implicit_internal.h"

/* ---------------------------------------------------------------- modular kernels ---------- */

slong _cb_implicit_eval_nmod_work(slong N)
{
    return FLINT_MAX(cb_poly3_len((int)N), 4 * (N + 1));
}

ulong _cb_implicit_eval_nmod(const ulong *Fp, slong N, const ulong X[4], nmod_t mod,
                             ulong *work)
{
    slong len = cb_poly3_len((int)N);
    if (X[3] != 0) {
        /* F(X) = w^N F(x/w, y/w, z/w, 1): a table of the monomials of degree <= N in the
         * dehomogenised point, one product each, then one dot product with lazy reduction. */
        ulong wi = n_invmod(X[3], mod.n);
        ulong x = nmod_mul(X[0], wi, mod), y = nmod_mul(X[1], wi, mod),
              z = nmod_mul(X[2], wi, mod);
        ulong *mono = work;
        mono[0] = 1;
        for (slong t = 1; t <= N; t++) {
            slong lo = cb_poly3_len((int)t - 1), plo = t >= 2 ? cb_poly3_len((int)t - 2) : 0;
            slong k = lo;
            for (slong j = 0; j < lo - plo; j++) /* x times every monomial of degree t - 1 */
                mono[k++] = nmod_mul(mono[plo + j], x, mod);
            for (slong j = 0; j < t; j++) /* y times y^(t-1-j) z^j */
                mono[k++] = nmod_mul(mono[lo - t + j], y, mod);
            mono[k] = nmod_mul(mono[lo - 1], z, mod); /* z^t */
        }
        ulong v = _nmod_vec_dot(Fp, mono, len, mod, _nmod_vec_dot_bound_limbs(len, mod));
        return nmod_mul(v, nmod_pow_ui(X[3], (ulong)N, mod), mod);
    }
    /* w = 0 mod p: only the terms of degree N survive. */
    ulong *px = work, *py = work + (N + 1), *pz = work + 2 * (N + 1);
    px[0] = py[0] = pz[0] = 1;
    for (slong e = 1; e <= N; e++) {
        px[e] = nmod_mul(px[e - 1], X[0], mod);
        py[e] = nmod_mul(py[e - 1], X[1], mod);
        pz[e] = nmod_mul(pz[e - 1], X[2], mod);
    }
    ulong acc = 0;
    slong idx = N >= 1 ? cb_poly3_len((int)N - 1) : 0;
    for (slong m = 0; m <= N; m++)
        for (slong k = 0; k <= m; k++, idx++) {
            ulong mono = nmod_mul(px[N - m], nmod_mul(py[m - k], pz[k], mod), mod);
            acc = nmod_add(acc, nmod_mul(Fp[idx], mono, mod), mod);
        }
    return acc;
}

void _cb_nmod_divdiff(ulong *c, slong stride, slong L, nmod_t mod)
{
    for (slong l = 1; l <= L; l++) {
        ulong inv = n_invmod((ulong)l, mod.n); /* nodes i and i - l are l apart */
        for (slong i = L; i >= l; i--)
            c[i * stride] = nmod_mul(nmod_sub(c[i * stride], c[(i - 1) * stride], mod), inv, mod);
    }
}

void _cb_nmod_newton_to_mono(ulong *c, slong stride, slong L, nmod_t mod, ulong *tmp)
{
    /* Horner with the factors (x - i): r <- r (x - i) + c_i, from i = L - 1 down to 0. */
    for (slong k = 0; k <= L; k++)
        tmp[k] = 0;
    tmp[0] = c[L * stride];
    for (slong i = L - 1; i >= 0; i--) {
        ulong ni = nmod_neg(nmod_set_ui((ulong)i, mod), mod);
        for (slong k = L - i; k >= 1; k--)
            tmp[k] = nmod_add(tmp[k - 1], nmod_mul(tmp[k], ni, mod), mod);
        tmp[0] = nmod_add(nmod_mul(tmp[0], ni, mod), c[i * stride], mod);
    }
    for (slong k = 0; k <= L; k++)
        c[k * stride] = tmp[k];
}

slong _cb_fmpz_vec_l1_bits(const fmpz *v, slong n)
{
    fmpz_t s;
    fmpz_init(s);
    for (slong i = 0; i < n; i++)
        if (fmpz_sgn(v + i) >= 0)
            fmpz_add(s, s, v + i);
        else
            fmpz_sub(s, s, v + i);
    slong b = (slong)fmpz_bits(s);
    fmpz_clear(s);
    return b;
}

ulong _cb_prime_seq_next(_cb_prime_seq *seq, ulong prev)
{
    ulong last = seq->start;
    for (int i = 0; i < CB_PRIME_SEQ_LEN; i++) {
        ulong q = atomic_load_explicit(seq->p + i, memory_order_relaxed);
        if (q == 0) {
            q = n_nextprime(last, 1);
            atomic_store_explicit(seq->p + i, q, memory_order_relaxed);
        }
        if (q > prev)
            return q;
        last = q;
    }
    return n_nextprime(prev, 1);
}

ulong _cb_crt_prime(ulong prev)
{
    static _cb_prime_seq crt = {UWORD(1) << 62, {0}};
    return _cb_prime_seq_next(&crt, prev);
}

/* ---------------------------------------------------------------- the F type --------------- */

void cb_implicit_init(cb_implicit_t F)
{
    F->deg = -1;
    F->c = NULL;
    F->cd = NULL;
    F->exp = 0;
    F->rank = 0;
    F->factored = 0;
}

void cb_implicit_clear(cb_implicit_t F)
{
    if (F->c)
        _fmpz_vec_clear(F->c, cb_poly3_len((int)F->deg));
    flint_free(F->cd);
    cb_implicit_init(F);
}

void cb_implicit_swap(cb_implicit_t F, cb_implicit_t G)
{
    cb_implicit_struct t = *F;
    *F = *G;
    *G = t;
}

/* Takes over c (cb_poly3_len(deg) integers): primitive part, sign, double copy. */
static void implicit_adopt(cb_implicit_t F, fmpz *c, slong deg)
{
    slong len = cb_poly3_len((int)deg), rank = F->rank;
    int factored = F->factored;
    cb_implicit_clear(F);
    F->rank = rank;
    F->factored = factored;
    fmpz_t g;
    fmpz_init(g);
    _fmpz_vec_content(g, c, len);
    for (slong i = 0; i < len; i++)
        if (!fmpz_is_zero(c + i)) {
            if (fmpz_sgn(c + i) < 0)
                fmpz_neg(g, g);
            break;
        }
    if (!fmpz_is_zero(g) && !fmpz_is_one(g))
        _fmpz_vec_scalar_divexact_fmpz(c, c, len, g);
    fmpz_clear(g);
    F->deg = deg;
    F->c = c;
    F->cd = flint_malloc((size_t)len * sizeof(double));
    F->exp = _cb_fmpz_vec_get_d_scaled(F->cd, c, len);
}

double cb_implicit_eval_d(const cb_implicit_t F, const double X[3])
{
    slong N = F->deg;
    double px[CB_POLY3_MAX_DEGREE + 1], py[CB_POLY3_MAX_DEGREE + 1],
        pz[CB_POLY3_MAX_DEGREE + 1];
    px[0] = py[0] = pz[0] = 1.0;
    for (slong e = 1; e <= N; e++) {
        px[e] = px[e - 1] * X[0];
        py[e] = py[e - 1] * X[1];
        pz[e] = pz[e - 1] * X[2];
    }
    double acc = 0.0;
    slong idx = 0;
    for (slong t = 0; t <= N; t++)
        for (slong m = 0; m <= t; m++)
            for (slong k = 0; k <= m; k++, idx++)
                acc += F->cd[idx] * px[t - m] * py[m - k] * pz[k];
    return acc;
}

void cb_implicit_get_mpoly(fmpz_mpoly_t out, const cb_implicit_t F, const fmpz_mpoly_ctx_t ctx)
{
    slong nv = ctx->minfo->nvars;
    ulong *e = flint_calloc((size_t)nv, sizeof(ulong));
    fmpz_mpoly_zero(out, ctx);
    slong idx = 0;
    for (slong t = 0; t <= F->deg; t++)
        for (slong m = 0; m <= t; m++)
            for (slong k = 0; k <= m; k++, idx++) {
                if (fmpz_is_zero(F->c + idx))
                    continue;
                e[0] = (ulong)(t - m);
                e[1] = (ulong)(m - k);
                e[2] = (ulong)k;
                e[3] = (ulong)(F->deg - t);
                fmpz_mpoly_push_term_fmpz_ui(out, F->c + idx, e, ctx);
            }
    fmpz_mpoly_sort_terms(out, ctx);
    fmpz_mpoly_combine_like_terms(out, ctx);
    flint_free(e);
}

/* Dense coefficients (layout of F, degree *deg) of a homogeneous mpoly in (x, y, z, w). */
static fmpz *mpoly_to_dense(slong *deg, const fmpz_mpoly_t A, const fmpz_mpoly_ctx_t ctx)
{
    slong N = fmpz_mpoly_total_degree_si(A, ctx);
    fmpz *c = _fmpz_vec_init(cb_poly3_len((int)N));
    ulong e[4];
    for (slong i = 0; i < fmpz_mpoly_length(A, ctx); i++) {
        fmpz_mpoly_get_term_exp_ui(e, A, i, ctx);
        fmpz_mpoly_get_term_coeff_fmpz(c + cb_poly3_index((int)e[0], (int)e[1], (int)e[2]),
                                       A, i, ctx);
    }
    *deg = N;
    return c;
}

/* ---------------------------------------------------------------- vanishing proof ---------- */

void cb_implicit_vanishes(int *vanishes, const cb_implicit_t F, const cb_dixon_patch_t P)
{
    slong N = F->deg, m = P->m, n = P->n, plen = _cb_dixon_patch_len(P);
    slong flen = cb_poly3_len((int)N);
    slong pbits = 0;
    for (int q = 0; q < 4; q++)
        pbits = FLINT_MAX(pbits, _cb_fmpz_vec_l1_bits(P->coef + q * plen, plen));
    slong need = _cb_fmpz_vec_l1_bits(F->c, flen) + N * pbits + 1;

    ulong *Fp = flint_malloc((size_t)flen * sizeof(ulong));
    ulong *cp = flint_malloc((size_t)(4 * plen) * sizeof(ulong));
    ulong *pw = flint_malloc((size_t)_cb_implicit_eval_nmod_work(N) * sizeof(ulong));
    ulong p = 0;
    slong have = 0; /* product of primes so far >= 2^have */
    int ok = 1;
    while (ok && have <= need) {
        p = _cb_crt_prime(p);
        nmod_t mod;
        nmod_init(&mod, p);
        _fmpz_vec_get_nmod_vec(Fp, F->c, flen, mod);
        _cb_dixon_patch_reduce(cp, P, mod);
        for (slong i = 0; ok && i <= N * m; i++)
            for (slong j = 0; ok && j <= N * n; j++) {
                ulong X[4];
                _cb_dixon_patch_eval_nmod(X, cp, m, n, (ulong)i, (ulong)j, mod);
                ok = _cb_implicit_eval_nmod(Fp, N, X, mod, pw) == 0;
            }
        have += 62;
    }
    flint_free(Fp);
    flint_free(cp);
    flint_free(pw);
    *vanishes = ok;
}

/* ---------------------------------------------------------------- Dixon determinant -------- */

/* The determinant of D restricted to rows x cols (r of each), interpolated as a homogeneous
 * polynomial of degree r and lifted by CRT; returns its dense coefficients. */
static fmpz *dixon_minor(const cb_dixon_pencil_t D, const slong *rows, const slong *cols,
                         slong r)
{
    slong s = D->size, len = cb_poly3_len((int)r);
    /* Bound: the determinant of a matrix of linear forms has coefficient 1-norm at most the
     * permanent of the matrix of entry 1-norms, itself at most the product of its row sums. */
    slong need = 1;
    fmpz_t rs;
    fmpz_init(rs);
    for (slong i = 0; i < r; i++) {
        fmpz_zero(rs);
        for (slong j = 0; j < r; j++)
            for (int q = 0; q < 4; q++) {
                const fmpz *e = fmpz_mat_entry(D->D[q], rows[i], cols[j]);
                if (fmpz_sgn(e) >= 0)
                    fmpz_add(rs, rs, e);
                else
                    fmpz_sub(rs, rs, e);
            }
        need += (slong)fmpz_bits(rs);
    }
    fmpz_clear(rs);

    fmpz *c = _fmpz_vec_init(len);
    fmpz_t M;
    fmpz_init_set_ui(M, 1);
    ulong *Dp = flint_malloc((size_t)(4 * s * s) * sizeof(ulong));
    ulong *val = flint_malloc((size_t)len * sizeof(ulong));
    ulong *line = flint_malloc((size_t)(r + 1) * sizeof(ulong));
    ulong *tmp = flint_malloc((size_t)(r + 1) * sizeof(ulong));
    slong *lidx = flint_malloc((size_t)(r + 1) * sizeof(slong));
    ulong p = 0;
    while ((slong)fmpz_bits(M) - 1 <= need) {
        p = _cb_crt_prime(p);
        nmod_t mod;
        nmod_init(&mod, p);
        _cb_dixon_pencil_reduce(Dp, D, mod);
        nmod_mat_t A;
        nmod_mat_init(A, r, r, p);
        slong s2 = s * s;
        for (slong t = 0; t <= r; t++)
            for (slong mm = 0; mm <= t; mm++)
                for (slong k = 0; k <= mm; k++) {
                    ulong X[4] = {(ulong)(t - mm), (ulong)(mm - k), (ulong)k, 1};
                    for (slong i = 0; i < r; i++)
                        for (slong j = 0; j < r; j++) {
                            slong e = rows[i] * s + cols[j];
                            ulong a = nmod_mul(X[0], Dp[e], mod);
                            a = nmod_add(a, nmod_mul(X[1], Dp[s2 + e], mod), mod);
                            a = nmod_add(a, nmod_mul(X[2], Dp[2 * s2 + e], mod), mod);
                            nmod_mat_entry(A, i, j) = nmod_add(a, Dp[3 * s2 + e], mod);
                        }
                    val[cb_poly3_index((int)X[0], (int)X[1], (int)X[2])] = nmod_mat_det(A);
                }
        nmod_mat_clear(A);
        /* Divided differences along x, y, z on the lower set i + j + k <= r, then the Newton
         * bases to monomials along each variable (see cb_implicit_from_dixon). */
        for (int pass = 0; pass < 2; pass++)
            for (int dir = 0; dir < 3; dir++)
                for (slong a = 0; a <= r; a++)
                    for (slong b = 0; a + b <= r; b++) {
                        slong L = r - a - b;
                        for (slong i = 0; i <= L; i++) {
                            /* the line runs along variable dir; a, b fix the others */
                            slong e[3];
                            e[dir] = i;
                            e[(dir + 1) % 3] = a;
                            e[(dir + 2) % 3] = b;
                            lidx[i] = cb_poly3_index((int)e[0], (int)e[1], (int)e[2]);
                            line[i] = val[lidx[i]];
                        }
                        if (pass == 0)
                            _cb_nmod_divdiff(line, 1, L, mod);
                        else
                            _cb_nmod_newton_to_mono(line, 1, L, mod, tmp);
                        for (slong i = 0; i <= L; i++)
                            val[lidx[i]] = line[i];
                    }
        fmpz_t Mold;
        fmpz_init_set(Mold, M);
        for (slong i = 0; i < len; i++)
            fmpz_CRT_ui(c + i, c + i, Mold, val[i], p, 1);
        fmpz_mul_ui(M, M, p);
        fmpz_clear(Mold);
    }
    fmpz_clear(M);
    flint_free(Dp);
    flint_free(val);
    flint_free(line);
    flint_free(tmp);
    flint_free(lidx);
    return c;
}

/* Rows and columns of a non-singular r x r submatrix of D(X) for a random X modulo a random
 * prime; 0 if the elimination there found fewer than r pivots. */
static int dixon_pick_minor(slong *rows, slong *cols, const cb_dixon_pencil_t D, slong r,
                            flint_rand_t st)
{
    slong s = D->size;
    nmod_t mod;
    nmod_init(&mod, n_randprime(st, 62, 1));
    ulong *Dp = flint_malloc((size_t)(4 * s * s) * sizeof(ulong));
    _cb_dixon_pencil_reduce(Dp, D, mod);
    ulong X[4];
    for (int q = 0; q < 4; q++)
        X[q] = n_randint(st, mod.n);
    nmod_mat_t M;
    nmod_mat_init(M, s, s, mod.n);
    _cb_dixon_pencil_eval_nmod(M, Dp, s, X, mod);
    slong got = _cb_nmod_mat_pivots(rows, cols, M);
    nmod_mat_clear(M);
    flint_free(Dp);
    return got == r;
}

cb_status cb_implicit_from_dixon(cb_implicit_t F, const cb_dixon_pencil_t D,
                                 const cb_dixon_patch_t P, cb_error *err)
{
    slong r = cb_dixon_pencil_rank(D), s = D->size;
    if (r == 0)
        return cb_error_set(err, CB_ERR_INVALID, "the Dixon matrix vanishes identically: the "
                            "components of the patch share a common factor or it is degenerate");
    if (r > CB_POLY3_MAX_DEGREE)
        return cb_error_set(err, CB_ERR_UNSUPPORTED, "Dixon rank %ld: implicit degree above %d "
                            "is not supported", (long)r, CB_POLY3_MAX_DEGREE);
    slong *rows = flint_malloc((size_t)s * sizeof(slong));
    slong *cols = flint_malloc((size_t)s * sizeof(slong));
    flint_rand_t st;
    flint_randinit(st);
    flint_randseed(st, CB_DIXON_SEED, CB_DIXON_SEED ^ 0x7f4au);
    int found = 0;
    for (int attempt = 0; attempt < 8 && !found; attempt++)
        found = dixon_pick_minor(rows, cols, D, r, st);
    flint_randclear(st);
    if (!found) {
        flint_free(rows);
        flint_free(cols);
        return cb_error_set(err, CB_ERR_NUMERIC, "no non-singular %ld x %ld minor of the Dixon "
                            "matrix found at 8 random points", (long)r, (long)r);
    }
    fmpz *c = dixon_minor(D, rows, cols, r);
    flint_free(rows);
    flint_free(cols);

    cb_implicit_t G;
    cb_implicit_init(G);
    G->rank = r;
    implicit_adopt(G, c, r);
    cb_status ret = CB_OK;
    int vanishes = 0;
    if (r == s) {
        cb_implicit_vanishes(&vanishes, G, P);
        if (vanishes)
            cb_implicit_swap(F, G);
    } else {
        /* Base points: the minor is F times factors that do not vanish on the surface. */
        fmpz_mpoly_ctx_t ctx;
        fmpz_mpoly_ctx_init(ctx, 4, ORD_DEGREVLEX);
        fmpz_mpoly_t A;
        fmpz_mpoly_init(A, ctx);
        cb_implicit_get_mpoly(A, G, ctx);
        fmpz_mpoly_factor_t fac;
        fmpz_mpoly_factor_init(fac, ctx);
        if (!fmpz_mpoly_factor(fac, A, ctx))
            ret = cb_error_set(err, CB_ERR_NUMERIC, "factorisation of the degree %ld Dixon "
                               "minor failed", (long)r);
        for (slong i = 0; ret == CB_OK && i < fac->num && !vanishes; i++) {
            if (fmpz_mpoly_total_degree_si(fac->poly + i, ctx) < 1)
                continue;
            slong deg;
            fmpz *fc = mpoly_to_dense(&deg, fac->poly + i, ctx);
            cb_implicit_t H;
            cb_implicit_init(H);
            H->rank = r;
            H->factored = 1;
            implicit_adopt(H, fc, deg);
            cb_implicit_vanishes(&vanishes, H, P);
            if (vanishes)
                cb_implicit_swap(F, H);
            cb_implicit_clear(H);
        }
        fmpz_mpoly_factor_clear(fac, ctx);
        fmpz_mpoly_clear(A, ctx);
        fmpz_mpoly_ctx_clear(ctx);
    }
    cb_implicit_clear(G);
    if (ret == CB_OK && !vanishes)
        ret = cb_error_set(err, CB_ERR_NUMERIC, "the Dixon %s of degree %ld does not vanish on "
                           "the patch", r == s ? "determinant" : "minor", (long)r);
    return ret;
}

/* out = sum_k a[k] x_k + b w (x_k the variables 0..2, w variable 3). */
static void linear_form(fmpz_mpoly_t out, const fmpz *a, const fmpz_t b,
                        const fmpz_mpoly_ctx_t ctx)
{
    fmpz_mpoly_t g;
    fmpz_mpoly_init(g, ctx);
    fmpz_mpoly_zero(out, ctx);
    for (int k = 0; k < 4; k++) {
        fmpz_mpoly_gen(g, k, ctx);
        fmpz_mpoly_scalar_mul_fmpz(g, g, k < 3 ? a + k : b, ctx);
        fmpz_mpoly_add(out, out, g, ctx);
    }
    fmpz_mpoly_clear(g, ctx);
}

/* A += c B (sub: A -= c B). */
static void mpoly_addmul(fmpz_mpoly_t A, const fmpz_mpoly_t B, const fmpz_t c, int sub,
                         const fmpz_mpoly_ctx_t ctx)
{
    fmpz_mpoly_t t;
    fmpz_mpoly_init(t, ctx);
    fmpz_mpoly_scalar_mul_fmpz(t, B, c, ctx);
    if (sub)
        fmpz_mpoly_sub(A, A, t, ctx);
    else
        fmpz_mpoly_add(A, A, t, ctx);
    fmpz_mpoly_clear(t, ctx);
}

cb_status cb_implicit_from_analytic(cb_implicit_t F, const cb_analytic_surface *s,
                                    cb_error *err)
{
    /* The doubles of the frame (x, y, z, o) and of the shape (r1, r2, r3, tan a) as integers
     * V 2^e with one exponent e <= 0. */
    double v[16];
    const cb_frame *f = &s->frame;
    for (int k = 0; k < 3; k++) {
        v[k] = f->x[k];
        v[3 + k] = f->y[k];
        v[6 + k] = f->z[k];
        v[9 + k] = f->o[k];
    }
    v[12] = s->r1;
    v[13] = s->r2;
    v[14] = s->r3;
    v[15] = s->kind == CB_ANALYTIC_CONE ? tan(s->angle) : 0;
    for (int k = 0; k < 16; k++)
        if (!isfinite(v[k]))
            return cb_error_set(err, CB_ERR_NUMERIC, "%s: non-finite frame or shape value",
                                cb_analytic_kind_name(s->kind));
    fmpz *V = _fmpz_vec_init(16);
    slong e = _cb_dyadic_to_fmpz(V, v, 16);
    if (e > 0) {
        _fmpz_vec_scalar_mul_2exp(V, V, 16, (ulong)e);
        e = 0;
    }
    ulong me = (ulong)(-e);
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_ctx_init(ctx, 4, ORD_DEGREVLEX);
    /* L[i] = 2^(-2e) (local coordinate i) = 2^(-e) sum_k Frame_ik x_k - sum_k Frame_ik O_k w,
     * lengths scaled alike: R[j] = 2^(-2e) r_j = 2^(-e) V_j. */
    fmpz_mpoly_t L[3], A, B, T, W;
    fmpz a[3], R[3];
    fmpz_t b;
    fmpz_init(b);
    for (int i = 0; i < 3; i++) {
        fmpz_init(a + i);
        fmpz_init(R + i);
        fmpz_mul_2exp(R + i, V + 12 + i, me);
    }
    for (int i = 0; i < 3; i++) {
        fmpz_mpoly_init(L[i], ctx);
        fmpz_zero(b);
        for (int k = 0; k < 3; k++) {
            fmpz_mul_2exp(a + k, V + 3 * i + k, me);
            fmpz_submul(b, V + 3 * i + k, V + 9 + k);
        }
        linear_form(L[i], a, b, ctx);
    }
    fmpz_mpoly_init(A, ctx);
    fmpz_mpoly_init(B, ctx);
    fmpz_mpoly_init(T, ctx);
    fmpz_mpoly_init(W, ctx);
    fmpz_mpoly_gen(W, 3, ctx);
    /* rho2 = L0^2 + L1^2 */
    fmpz_mpoly_mul(A, L[0], L[0], ctx);
    fmpz_mpoly_mul(T, L[1], L[1], ctx);
    fmpz_mpoly_add(A, A, T, ctx);
    fmpz_t c;
    fmpz_init(c);
    switch (s->kind) {
    case CB_ANALYTIC_PLANE:
        fmpz_mpoly_set(A, L[2], ctx);
        break;
    case CB_ANALYTIC_CYLINDER: /* rho^2 - r^2 w^2 */
        fmpz_mul(c, R + 0, R + 0);
        fmpz_mpoly_pow_ui(T, W, 2, ctx);
        mpoly_addmul(A, T, c, 1, ctx);
        break;
    case CB_ANALYTIC_SPHERE: /* rho^2 + z^2 - r^2 w^2 */
        fmpz_mpoly_mul(T, L[2], L[2], ctx);
        fmpz_mpoly_add(A, A, T, ctx);
        fmpz_mul(c, R + 0, R + 0);
        fmpz_mpoly_pow_ui(T, W, 2, ctx);
        mpoly_addmul(A, T, c, 1, ctx);
        break;
    case CB_ANALYTIC_CONE: /* 2^(-2e) rho^2 - (2^(-e) r w + t z)^2, t = tan a 2^(-e) */
        fmpz_one(c);
        fmpz_mul_2exp(c, c, 2 * me);
        fmpz_mpoly_scalar_mul_fmpz(A, A, c, ctx);
        fmpz_mul_2exp(c, R + 0, me);
        fmpz_mpoly_scalar_mul_fmpz(B, W, c, ctx);
        mpoly_addmul(B, L[2], V + 15, 0, ctx);
        fmpz_mpoly_mul(T, B, B, ctx);
        fmpz_mpoly_sub(A, A, T, ctx);
        break;
    case CB_ANALYTIC_TORUS: /* (rho^2 + z^2 + (R^2 - r^2) w^2)^2 - 4 R^2 rho^2 w^2 */
        fmpz_mpoly_mul(T, L[2], L[2], ctx);
        fmpz_mpoly_add(B, A, T, ctx);
        fmpz_mul(c, R + 0, R + 0);
        fmpz_submul(c, R + 1, R + 1);
        fmpz_mpoly_pow_ui(T, W, 2, ctx);
        mpoly_addmul(B, T, c, 0, ctx);
        fmpz_mpoly_mul(B, B, B, ctx);
        fmpz_mul(c, R + 0, R + 0);
        fmpz_mul_2exp(c, c, 2);
        fmpz_mpoly_mul(A, A, T, ctx);
        mpoly_addmul(B, A, c, 1, ctx);
        fmpz_mpoly_swap(A, B, ctx);
        break;
    case CB_ANALYTIC_ELLIPSOID: { /* b^2 c^2 x^2 + a^2 c^2 y^2 + a^2 b^2 z^2 - a^2 b^2 c^2 w^2 */
        fmpz q[3];
        fmpz_mpoly_zero(A, ctx);
        for (int i = 0; i < 3; i++) {
            fmpz_init(q + i);
            fmpz_mul(q + i, R + i, R + i);
        }
        for (int i = 0; i < 3; i++) {
            fmpz_mul(c, q + (i + 1) % 3, q + (i + 2) % 3);
            fmpz_mpoly_mul(T, L[i], L[i], ctx);
            mpoly_addmul(A, T, c, 0, ctx);
        }
        fmpz_mul(c, q + 0, q + 1);
        fmpz_mul(c, c, q + 2);
        fmpz_mpoly_pow_ui(T, W, 2, ctx);
        mpoly_addmul(A, T, c, 1, ctx);
        for (int i = 0; i < 3; i++)
            fmpz_clear(q + i);
        break;
    }
    }
    slong N = fmpz_mpoly_total_degree_si(A, ctx);
    cb_status st = CB_OK;
    if (fmpz_mpoly_is_zero(A, ctx) || N < 1) {
        st = cb_error_set(err, CB_ERR_INVALID, "%s equation is constant",
                          cb_analytic_kind_name(s->kind));
    } else {
        slong deg;
        fmpz *cc = mpoly_to_dense(&deg, A, ctx);
        F->rank = 0;
        F->factored = 0;
        implicit_adopt(F, cc, deg);
    }
    fmpz_clear(c);
    fmpz_clear(b);
    for (int i = 0; i < 3; i++) {
        fmpz_clear(a + i);
        fmpz_clear(R + i);
        fmpz_mpoly_clear(L[i], ctx);
    }
    fmpz_mpoly_clear(A, ctx);
    fmpz_mpoly_clear(B, ctx);
    fmpz_mpoly_clear(T, ctx);
    fmpz_mpoly_clear(W, ctx);
    fmpz_mpoly_ctx_clear(ctx);
    _fmpz_vec_clear(V, 16);
    return st;
}

cb_status cb_implicit_from_plane_patch(cb_implicit_t F, const cb_dixon_patch_t P, cb_error *err)
{
    slong len = (P->m + 1) * (P->n + 1);
    fmpz_mat_t Ct, X;
    fmpz_mat_init(Ct, len, 4);
    fmpz_mat_init(X, 4, 4);
    for (int q = 0; q < 4; q++)
        for (slong i = 0; i < len; i++)
            fmpz_set(fmpz_mat_entry(Ct, i, q), P->coef + q * len + i);
    slong nul = fmpz_mat_nullspace(X, Ct);
    fmpz_mat_clear(Ct);
    if (nul != 1) {
        fmpz_mat_clear(X);
        return cb_error_set(err, CB_ERR_INVALID,
                            "plane of a patch: its homogeneous coefficients span %ld "
                            "dimensions, not 3 (%s)",
                            (long)(4 - nul), nul > 1 ? "the patch collapses" : "not planar");
    }
    /* L . (a, b, c, d) = 0: F = L0 x + L1 y + L2 z + L3 w in the cb_poly3 layout
     * (index 0 is w, 1 x, 2 y, 3 z). */
    fmpz *c = _fmpz_vec_init(cb_poly3_len(1));
    fmpz_set(c + 0, fmpz_mat_entry(X, 3, 0));
    fmpz_set(c + cb_poly3_index(1, 0, 0), fmpz_mat_entry(X, 0, 0));
    fmpz_set(c + cb_poly3_index(0, 1, 0), fmpz_mat_entry(X, 1, 0));
    fmpz_set(c + cb_poly3_index(0, 0, 1), fmpz_mat_entry(X, 2, 0));
    fmpz_mat_clear(X);
    F->rank = 0;
    F->factored = 0;
    implicit_adopt(F, c, 1);
    return CB_OK;
}

cb_status cb_implicit_plane_through(cb_implicit_t F, const double h[3][4], cb_error *err)
{
    double v[12];
    for (int i = 0; i < 3; i++)
        for (int q = 0; q < 4; q++) {
            v[4 * i + q] = h[i][q];
            if (!isfinite(h[i][q]))
                return cb_error_set(err, CB_ERR_INVALID, "plane through points: non-finite value");
        }
    fmpz *V = _fmpz_vec_init(12);
    _cb_dyadic_to_fmpz(V, v, 12);
    fmpz_mat_t M, X;
    fmpz_mat_init(M, 3, 4);
    fmpz_mat_init(X, 4, 4);
    for (int i = 0; i < 3; i++)
        for (int q = 0; q < 4; q++)
            fmpz_set(fmpz_mat_entry(M, i, q), V + 4 * i + q);
    slong nul = fmpz_mat_nullspace(X, M);
    cb_status st = CB_OK;
    if (nul != 1) {
        st = cb_error_set(err, CB_ERR_INVALID, "plane through points: the points are collinear");
    } else {
        fmpz *c = _fmpz_vec_init(cb_poly3_len(1));
        fmpz_set(c + 0, fmpz_mat_entry(X, 3, 0));
        fmpz_set(c + cb_poly3_index(1, 0, 0), fmpz_mat_entry(X, 0, 0));
        fmpz_set(c + cb_poly3_index(0, 1, 0), fmpz_mat_entry(X, 1, 0));
        fmpz_set(c + cb_poly3_index(0, 0, 1), fmpz_mat_entry(X, 2, 0));
        F->rank = 0;
        F->factored = 0;
        implicit_adopt(F, c, 1);
    }
    fmpz_mat_clear(M);
    fmpz_mat_clear(X);
    _fmpz_vec_clear(V, 12);
    return st;
}

int cb_implicit_choose(const cb_dixon_pencil_t DP, const cb_dixon_pencil_t DQ)
{
    slong rp = cb_dixon_pencil_rank(DP), rq = cb_dixon_pencil_rank(DQ);
    if (rp != rq)
        return rq < rp;
    return DQ->m * DQ->n < DP->m * DP->n;
}
