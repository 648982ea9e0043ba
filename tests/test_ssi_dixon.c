/* Dixon implicitisation, phi = F(Q) and inversion (ssi/dixon.h, ssi/implicit.h,
 * ssi/inversion.h): the paper's Example 1 and 2 numbers, degrees and exact vanishing on random
 * patches, exact sphere and torus equations from base-point patches, phi at known common
 * points, inversion of sampled points, degenerate patches. */
#include <math.h>
#include <stdlib.h>

#include <flint/fmpq.h>
#include <flint/fmpz_mpoly.h>

#include "brep/analytic.h"
#include "check.h"
#include "ssi/dixon.h"
#include "ssi/implicit.h"
#include "ssi/inversion.h"

/* ---------------------------------------------------------------- helpers ------------------ */

/* A rational Bezier patch of degree (m, n) on [0, 1]^2 from Euclidean points and weights
 * (NULL: polynomial). */
static void bezier(cb_nurbs_surface_t s, int m, int n, const double *pts, const double *w)
{
    double ku[2 * CB_MAX_BASIS], kv[2 * CB_MAX_BASIS];
    for (int i = 0; i <= m; i++) {
        ku[i] = 0.0;
        ku[m + 1 + i] = 1.0;
    }
    for (int j = 0; j <= n; j++) {
        kv[j] = 0.0;
        kv[n + 1 + j] = 1.0;
    }
    cb_error err;
    cb_status st = cb_nurbs_surface_make(s, m, n, ku, 2 * m + 2, kv, 2 * n + 2, pts, w, m + 1,
                                         n + 1, &err);
    CHECK(st == CB_OK, "bezier: %s", err.msg);
}

/* Random polynomial Bezier patch with integer coordinates in [-5, 5]. */
static void random_int_patch(cb_nurbs_surface_t s, int m, int n, check_rng *rng)
{
    double pts[3 * CB_MAX_BASIS * CB_MAX_BASIS];
    for (int k = 0; k < 3 * (m + 1) * (n + 1); k++)
        pts[k] = check_rng_int(rng, -5, 5);
    bezier(s, m, n, pts, NULL);
}

/* Dixon patch + pencil + implicit equation, checking each status. */
static int implicitise(cb_implicit_t F, cb_dixon_pencil_t D, cb_dixon_patch_t P,
                       const cb_nurbs_surface_t s, const char *what)
{
    cb_error err;
    cb_status st = cb_dixon_patch_set_bezier(P, s, &err);
    if (st == CB_OK)
        st = cb_dixon_pencil_set(D, P, &err);
    if (st == CB_OK)
        st = cb_implicit_from_dixon(F, D, P, &err);
    CHECK(st == CB_OK, "%s: %s", what, err.msg);
    return st == CB_OK;
}

/* phi(num_s / 2^ks, num_t / 2^kt) 2^(ks ds + kt dt), exactly. */
static void phi_at_dyadic(fmpz_t out, const cb_phi_t phi, slong ns, ulong ks, slong nt, ulong kt)
{
    fmpz_t term, p;
    fmpz_init(term);
    fmpz_init(p);
    fmpz_zero(out);
    for (slong i = 0; i <= phi->ds; i++)
        for (slong j = 0; j <= phi->dt; j++) {
            fmpz_set_si(p, ns);
            fmpz_pow_ui(p, p, (ulong)i);
            fmpz_mul(term, phi->c + i * (phi->dt + 1) + j, p);
            fmpz_set_si(p, nt);
            fmpz_pow_ui(p, p, (ulong)j);
            fmpz_mul(term, term, p);
            fmpz_mul_2exp(term, term, ks * (ulong)(phi->ds - i) + kt * (ulong)(phi->dt - j));
            fmpz_add(out, out, term);
        }
    fmpz_clear(term);
    fmpz_clear(p);
}

/* de Casteljau on the Bernstein coefficients of phi at local (sigma, tau) in [0, 1]^2. */
static double phi_bern_eval(const cb_phi_t phi, double sg, double ta)
{
    slong ds = phi->ds, dt = phi->dt;
    double *row = malloc((size_t)(ds + 1) * sizeof(double));
    double *tmp = malloc((size_t)(FLINT_MAX(ds, dt) + 1) * sizeof(double));
    for (slong i = 0; i <= ds; i++) {
        for (slong j = 0; j <= dt; j++)
            tmp[j] = phi->bern[i * (dt + 1) + j];
        for (slong r = 1; r <= dt; r++)
            for (slong j = 0; j <= dt - r; j++)
                tmp[j] = (1 - ta) * tmp[j] + ta * tmp[j + 1];
        row[i] = tmp[0];
    }
    for (slong r = 1; r <= ds; r++)
        for (slong i = 0; i <= ds - r; i++)
            row[i] = (1 - sg) * row[i] + sg * row[i + 1];
    double v = row[0];
    free(row);
    free(tmp);
    return v;
}

static double max_abs(const double *v, slong n)
{
    double m = 0.0;
    for (slong i = 0; i < n; i++)
        m = fmax(m, fabs(v[i]));
    return m;
}

/* The paper's Example 1 patch, power basis on [0, 1]^2. */
static void example1_patch(cb_dixon_patch_t P)
{
    static const struct {
        int q, i, j;
        double c;
    } t[] = {{0, 3, 0, -32}, {0, 1, 2, 96}, {0, 2, 0, 48}, {0, 1, 1, -96}, {0, 0, 2, -48},
             {0, 1, 0, 6},   {0, 0, 1, 48}, {0, 0, 0, -11}, {1, 2, 1, 96}, {1, 0, 3, -32},
             {1, 2, 0, -48}, {1, 1, 1, -96}, {1, 0, 2, 48}, {1, 1, 0, 48}, {1, 0, 1, 6},
             {1, 0, 0, -11}, {2, 2, 0, 24}, {2, 0, 2, -24}, {2, 1, 0, -24}, {2, 0, 1, 24},
             {3, 0, 0, 2}};
    double hc[64] = {0};
    for (size_t k = 0; k < sizeof t / sizeof t[0]; k++)
        hc[t[k].q * 16 + t[k].i * 4 + t[k].j] = t[k].c;
    const double box[4] = {0, 1, 0, 1};
    cb_error err;
    CHECK(cb_dixon_patch_set_power(P, 3, 3, hc, box, &err) == CB_OK, "example 1: %s", err.msg);
}

/* ---------------------------------------------------------------- Example 1 ---------------- */

static void test_example1(void)
{
    cb_dixon_patch_t P;
    cb_dixon_pencil_t D;
    cb_implicit_t F;
    cb_dixon_patch_init(P);
    cb_dixon_pencil_init(D);
    cb_implicit_init(F);
    example1_patch(P);
    cb_error err;
    CHECK(cb_dixon_pencil_set(D, P, &err) == CB_OK, "example 1 pencil: %s", err.msg);
    CHECK(D->size == 18, "size %ld", (long)D->size);

    /* The paper prints D[0][0] = 5184 (4x - 4y - 7z), D[0][1] = 10368 (11w + 2y + 4z). */
    const slong e00[4] = {4, -4, -7, 0}, e01[4] = {0, 2, 4, 11};
    int prop00 = 1, prop01 = 1;
    for (int q = 0; q < 4; q++) {
        prop00 = prop00 && fmpz_get_si(fmpz_mat_entry(D->D[q], 0, 0)) * e00[0] ==
                               fmpz_get_si(fmpz_mat_entry(D->D[0], 0, 0)) * e00[q];
        prop01 = prop01 && fmpz_get_si(fmpz_mat_entry(D->D[q], 0, 1)) * e01[1] ==
                               fmpz_get_si(fmpz_mat_entry(D->D[1], 0, 1)) * e01[q];
    }
    CHECK(prop00 && prop01, "D entries (0,0), (0,1) not proportional to the paper's");

    slong r = cb_dixon_pencil_rank(D);
    CHECK(r == 9, "rank %ld, expected 9", (long)r);
    const double X0[3] = {0.3, -0.7, 1.1};
    r = cb_dixon_pencil_rank_d(D, X0, 1e-10);
    CHECK(r == 9, "numerical rank %ld, expected 9", (long)r);

    cb_status st = cb_implicit_from_dixon(F, D, P, &err);
    CHECK(st == CB_OK, "example 1 implicit: %s", err.msg);
    CHECK(F->deg == 9, "degree %ld, expected 9", (long)F->deg);

    /* Independent exact check: F(a, b, c, d) composed symbolically is the zero polynomial. */
    fmpz_mpoly_ctx_t c4, c2;
    fmpz_mpoly_ctx_init(c4, 4, ORD_DEGREVLEX);
    fmpz_mpoly_ctx_init(c2, 2, ORD_DEGREVLEX);
    fmpz_mpoly_t Fm, comp, comp_bad;
    fmpz_mpoly_struct abcd[4];
    fmpz_mpoly_struct *args[4];
    fmpz_mpoly_init(Fm, c4);
    fmpz_mpoly_init(comp, c2);
    fmpz_mpoly_init(comp_bad, c2);
    const char *vars[2] = {"u", "v"};
    const char *src[4] = {"-32*u^3+96*u*v^2+48*u^2-96*u*v-48*v^2+6*u+48*v-11",
                          "96*u^2*v-32*v^3-48*u^2-96*u*v+48*v^2+48*u+6*v-11",
                          "24*u^2-24*v^2-24*u+24*v", "2"};
    for (int q = 0; q < 4; q++) {
        fmpz_mpoly_init(abcd + q, c2);
        fmpz_mpoly_set_str_pretty(abcd + q, src[q], vars, c2);
        args[q] = abcd + q;
    }
    cb_implicit_get_mpoly(Fm, F, c4);
    fmpz_mpoly_compose_fmpz_mpoly(comp, Fm, args, c4, c2);
    CHECK(fmpz_mpoly_is_zero(comp, c2), "F(P(u, v)) is not identically zero");
    /* ... and the test can fail: a perturbed F does not vanish. */
    fmpz_mpoly_t one;
    fmpz_mpoly_init(one, c4);
    fmpz_mpoly_set_ui(one, 1, c4);
    fmpz_mpoly_add(Fm, Fm, one, c4);
    fmpz_mpoly_compose_fmpz_mpoly(comp_bad, Fm, args, c4, c2);
    CHECK(!fmpz_mpoly_is_zero(comp_bad, c2), "perturbed F vanishes too");
    int van = 0;
    cb_implicit_vanishes(&van, F, P);
    CHECK(van, "cb_implicit_vanishes says no");
    for (int q = 0; q < 4; q++)
        fmpz_mpoly_clear(abcd + q, c2);
    fmpz_mpoly_clear(one, c4);
    fmpz_mpoly_clear(Fm, c4);
    fmpz_mpoly_clear(comp, c2);
    fmpz_mpoly_clear(comp_bad, c2);
    fmpz_mpoly_ctx_clear(c4);
    fmpz_mpoly_ctx_clear(c2);

    /* Inversion (Example 1 (2)). */
    const double X1[3] = {-0.8660864938, -2.474813428, 1.846465226};
    const double X2[3] = {0.1882746188, -2.534024645, 2.683854645};
    cb_inversion_params par;
    cb_inversion_params_default(&par);
    cb_inversion_t res;
    cb_inversion_init(res);
    st = cb_inversion_solve(res, D, P, X1, &par, &err);
    CHECK(st == CB_OK && res->n == 1 && res->inside, "X1: status %d, %ld solutions, inside %d",
          st, (long)res->n, res->inside);
    if (res->n >= 1) {
        printf("example 1: X1 -> (%.11f, %.10f), distance %.2g\n", res->pt[0].u, res->pt[0].v,
               res->pt[0].dist);
        CHECK(fabs(res->pt[0].u - 0.05514238183) < 1e-8 &&
                  fabs(res->pt[0].v - 0.2901757920) < 1e-8,
              "X1 -> (%.12f, %.12f)", res->pt[0].u, res->pt[0].v);
    }
    st = cb_inversion_solve(res, D, P, X2, &par, &err);
    CHECK(st == CB_OK && res->n == 1 && !res->inside, "X2: status %d, %ld solutions, inside %d",
          st, (long)res->n, res->inside);
    if (res->n >= 1) {
        printf("example 1: X2 -> (%.10f, %.10f), distance %.2g\n", res->pt[0].u, res->pt[0].v,
               res->pt[0].dist);
        CHECK(fabs(res->pt[0].u - 1.003407729) < 1e-8 &&
                  fabs(res->pt[0].v - 0.3274752700) < 1e-8,
              "X2 -> (%.12f, %.12f)", res->pt[0].u, res->pt[0].v);
    }
    /* A point off the surface has no preimage. */
    const double X3[3] = {X1[0] + 0.01, X1[1], X1[2]};
    st = cb_inversion_solve(res, D, P, X3, &par, &err);
    CHECK(st == CB_OK && res->n == 0 && !res->inside, "off-surface point: %ld solutions",
          (long)res->n);
    cb_inversion_clear(res);

    /* Example 2: phi = F(Q) on Q's box [-1, 1] x [0, 2]; the paper prints the rows t^24, t^22
     * and t^0 (even powers of s, s^18 first). */
    static const struct {
        int q, i, j;
        double c;
    } qt[] = {{0, 1, 2, 2}, {0, 1, 0, 2}, {1, 2, 3, -1}, {1, 2, 0, 1}, {1, 0, 3, -3},
              {1, 0, 0, 3}, {2, 3, 1, 2}, {2, 0, 1, 6}, {3, 2, 2, 1}, {3, 2, 0, 1},
              {3, 0, 2, 1}, {3, 0, 0, 1}};
    double hq[64] = {0};
    for (size_t k = 0; k < sizeof qt / sizeof qt[0]; k++)
        hq[qt[k].q * 16 + qt[k].i * 4 + qt[k].j] = qt[k].c;
    const double qbox[4] = {-1, 1, 0, 2};
    cb_dixon_patch_t Q;
    cb_dixon_patch_init(Q);
    CHECK(cb_dixon_patch_set_power(Q, 3, 3, hq, qbox, &err) == CB_OK, "Q: %s", err.msg);
    cb_phi_t phi;
    cb_phi_init(phi);
    st = cb_phi_compute(phi, F, Q, &err);
    CHECK(st == CB_OK, "example 2 phi: %s", err.msg);
    if (st == CB_OK) {
        static const long r24[10] = {1, 21, 192, 1000, 3258, 6858, 9288, 7776, 3645, 729};
        static const long r22[10] = {3, 51, 396, 1884, 6090, 13626, 20412, 19116, 9963, 2187};
        static const long r0[10] = {1, 9, 60, 252, 822, 1926, 3356, 3996, 2673, 729};
        const long *rows[3] = {r24, r22, r0};
        const slong tj[3] = {24, 22, 0};
        slong w = phi->dt + 1;
        /* phi = lambda paper: phi[i][j] 729 = phi[0][0] paper[i][j] */
        fmpz_t x, y;
        fmpz_init(x);
        fmpz_init(y);
        int ok = !fmpz_is_zero(phi->c);
        for (int rr = 0; rr < 3; rr++)
            for (int k = 0; k < 10; k++) {
                fmpz_mul_si(x, phi->c, rows[rr][k]);
                fmpz_mul_si(y, phi->c + (18 - 2 * k) * w + tj[rr], 729);
                ok = ok && fmpz_equal(x, y);
                if (k < 9) /* odd powers of s vanish */
                    ok = ok && fmpz_is_zero(phi->c + (17 - 2 * k) * w + tj[rr]);
            }
        /* t-degree 24 (of 27 possible): the paper's top row is t^24 */
        for (slong i = 0; i <= phi->ds; i++)
            for (slong j = 25; j <= phi->dt; j++)
                ok = ok && fmpz_is_zero(phi->c + i * w + j);
        CHECK(ok, "phi of Example 2 differs from the paper's rows t^24, t^22, t^0");
        fmpz_clear(x);
        fmpz_clear(y);
        /* Bernstein form over [-1, 1] x [0, 2] agrees with the power form. */
        double scale = max_abs(phi->bern, (phi->ds + 1) * w), worst = 0.0;
        for (int k = 0; k < 20; k++) {
            double sg = k / 19.0, ta = (k * 7 % 19) / 19.0;
            double a = phi_bern_eval(phi, sg, ta), b = cb_phi_eval_d(phi, -1 + 2 * sg, 2 * ta);
            worst = fmax(worst, fabs(a - b) / scale);
        }
        CHECK(worst < 1e-9, "Bernstein vs power form of phi: %g", worst);
    }
    cb_phi_clear(phi);
    cb_dixon_patch_clear(Q);
    cb_implicit_clear(F);
    cb_dixon_pencil_clear(D);
    cb_dixon_patch_clear(P);
}

/* ---------------------------------------------------------------- random patches ----------- */

/* Polynomial patches without base points: rank 2mn, degree 2mn, F(P) = 0 exactly; and a
 * perturbed F does not vanish (so the check can fail). */
static void test_random_polynomial(check_rng *rng)
{
    const int deg[2][2] = {{3, 3}, {2, 2}};
    const int trials[2] = {3, 5};
    for (int kind = 0; kind < 2; kind++)
        for (int trial = 0; trial < trials[kind]; trial++) {
            int m = deg[kind][0], n = deg[kind][1];
            cb_nurbs_surface_t s;
            cb_nurbs_surface_init(s);
            random_int_patch(s, m, n, rng);
            cb_dixon_patch_t P;
            cb_dixon_pencil_t D;
            cb_implicit_t F;
            cb_dixon_patch_init(P);
            cb_dixon_pencil_init(D);
            cb_implicit_init(F);
            if (implicitise(F, D, P, s, "random polynomial patch")) {
                slong r = cb_dixon_pencil_rank(D);
                CHECK(r == 2 * m * n, "(%d,%d) trial %d: rank %ld", m, n, trial, (long)r);
                CHECK(F->deg == 2 * m * n, "(%d,%d) trial %d: degree %ld", m, n, trial,
                      (long)F->deg);
                int van = 0;
                cb_implicit_vanishes(&van, F, P);
                CHECK(van, "(%d,%d) trial %d: F(P) != 0", m, n, trial);
                fmpz_add_ui(F->c + 3, F->c + 3, 1);
                cb_implicit_vanishes(&van, F, P);
                CHECK(!van, "(%d,%d) trial %d: perturbed F(P) = 0", m, n, trial);
                /* Numerical rank at a random point is full. */
                double X[3] = {check_rng_uniform(rng, -3, 3), check_rng_uniform(rng, -3, 3),
                               check_rng_uniform(rng, -3, 3)};
                r = cb_dixon_pencil_rank_d(D, X, 1e-10);
                CHECK(r == 2 * m * n, "(%d,%d) trial %d: numerical rank %ld", m, n, trial,
                      (long)r);
            }
            cb_implicit_clear(F);
            cb_dixon_pencil_clear(D);
            cb_dixon_patch_clear(P);
            cb_nurbs_surface_clear(s);
        }
}

/* ---------------------------------------------------------------- sphere and torus --------- */

/* Bernstein coefficients of the quarter circle (1 - t^2, 2t, 1 + t^2), t in [0, 1]: rational
 * weights, so the patch is exactly on the surface. */
static const double ARC_X[3] = {1, 1, 0}, ARC_Y[3] = {0, 1, 2}, ARC_W[3] = {1, 1, 2};

/* kind 0: unit sphere (cos v cos u, cos v sin u, sin v); kind 1: torus R = 2, r = 1. */
static void quadric_patch(cb_nurbs_surface_t s, int kind)
{
    double pts[27], w[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double rho = kind == 0 ? ARC_X[j] : 2 * ARC_W[j] + ARC_X[j];
            double h[4] = {rho * ARC_X[i], rho * ARC_Y[i], ARC_W[i] * ARC_Y[j],
                           ARC_W[i] * ARC_W[j]};
            for (int q = 0; q < 3; q++)
                pts[3 * (3 * i + j) + q] = h[q] / h[3];
            w[3 * i + j] = h[3];
        }
    bezier(s, 2, 2, pts, w);
}

static int mpoly_equal_str(const fmpz_mpoly_t A, const char *str, const fmpz_mpoly_ctx_t ctx)
{
    const char *vars[4] = {"x", "y", "z", "w"};
    fmpz_mpoly_t B;
    fmpz_mpoly_init(B, ctx);
    fmpz_mpoly_set_str_pretty(B, str, vars, ctx);
    int eq = fmpz_mpoly_equal(A, B, ctx);
    fmpz_mpoly_neg(B, B, ctx);
    eq = eq || fmpz_mpoly_equal(A, B, ctx);
    fmpz_mpoly_clear(B, ctx);
    return eq;
}

static void test_sphere_torus(void)
{
    const char *expect[2] = {"x^2+y^2+z^2-w^2",
                             "(x^2+y^2+z^2+3*w^2)^2-16*w^2*(x^2+y^2)"};
    const slong edeg[2] = {2, 4};
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_ctx_init(ctx, 4, ORD_DEGREVLEX);
    fmpz_mpoly_t A;
    fmpz_mpoly_init(A, ctx);
    for (int kind = 0; kind < 2; kind++) {
        cb_nurbs_surface_t s;
        cb_nurbs_surface_init(s);
        quadric_patch(s, kind);
        cb_dixon_patch_t P;
        cb_dixon_pencil_t D;
        cb_implicit_t F;
        cb_dixon_patch_init(P);
        cb_dixon_pencil_init(D);
        cb_implicit_init(F);
        if (implicitise(F, D, P, s, kind ? "torus patch" : "sphere patch")) {
            slong r = cb_dixon_pencil_rank(D);
            printf("%s patch: Dixon rank %ld of 8, implicit degree %ld\n",
                   kind ? "torus" : "sphere", (long)r, (long)F->deg);
            CHECK(r < 8, "%s: rank %ld, base points expected", kind ? "torus" : "sphere",
                  (long)r);
            CHECK(F->deg == edeg[kind], "%s: degree %ld", kind ? "torus" : "sphere",
                  (long)F->deg);
            cb_implicit_get_mpoly(A, F, ctx);
            CHECK(mpoly_equal_str(A, expect[kind], ctx), "%s: F is not %s",
                  kind ? "torus" : "sphere", expect[kind]);
        }
        cb_implicit_clear(F);
        cb_dixon_pencil_clear(D);
        cb_dixon_patch_clear(P);
        cb_nurbs_surface_clear(s);
    }

    /* The analytic route gives the same equations, and the plane has degree 1. */
    cb_frame fr;
    const double o[3] = {0, 0, 0}, ax[3] = {0, 0, 1};
    cb_error err;
    CHECK(cb_frame_make(&fr, o, ax, NULL, &err) == CB_OK, "frame: %s", err.msg);
    cb_analytic_surface sph, tor, pla;
    CHECK(cb_analytic_sphere(&sph, &fr, 1.0, &err) == CB_OK, "sphere: %s", err.msg);
    CHECK(cb_analytic_torus(&tor, &fr, 2.0, 1.0, &err) == CB_OK, "torus: %s", err.msg);
    CHECK(cb_analytic_plane(&pla, &fr, &err) == CB_OK, "plane: %s", err.msg);
    const cb_analytic_surface *an[3] = {&sph, &tor, &pla};
    const char *aexp[3] = {expect[0], expect[1], "z"};
    for (int k = 0; k < 3; k++) {
        cb_implicit_t F;
        cb_implicit_init(F);
        cb_status st = cb_implicit_from_analytic(F, an[k], &err);
        CHECK(st == CB_OK, "analytic %d: %s", k, err.msg);
        if (st == CB_OK) {
            cb_implicit_get_mpoly(A, F, ctx);
            CHECK(mpoly_equal_str(A, aexp[k], ctx), "analytic %s: F is not %s",
                  cb_analytic_kind_name(an[k]->kind), aexp[k]);
        }
        cb_implicit_clear(F);
    }
    fmpz_mpoly_clear(A, ctx);
    fmpz_mpoly_ctx_clear(ctx);
}

/* ---------------------------------------------------------------- phi ---------------------- */

/* Q translated so that Q(1/2, 1/4) = P(1/4, 3/4): phi vanishes exactly there, and not at an
 * unrelated point; the Bernstein form matches the power form and F(Q) evaluated directly has
 * the same sign. Both for a Dixon F and an analytic F. */
static void test_phi(check_rng *rng)
{
    int trials = 2;
    for (int trial = 0; trial < 2 * trials; trial++) {
        int analytic = trial % 2;
        cb_nurbs_surface_t s, q;
        cb_nurbs_surface_init(s);
        cb_nurbs_surface_init(q);
        cb_implicit_t F;
        cb_implicit_init(F);
        cb_error err;
        double target[3];
        int ok;
        if (analytic) {
            cb_frame fr;
            const double o[3] = {0.5, -0.25, 0.125}, ax[3] = {0, 0, 1};
            cb_analytic_surface sph;
            ok = cb_frame_make(&fr, o, ax, NULL, &err) == CB_OK &&
                 cb_analytic_sphere(&sph, &fr, 1.0, &err) == CB_OK &&
                 cb_implicit_from_analytic(F, &sph, &err) == CB_OK;
            CHECK(ok, "analytic sphere: %s", err.msg);
            target[0] = 1.5; /* o + (1, 0, 0) */
            target[1] = -0.25;
            target[2] = 0.125;
        } else {
            random_int_patch(s, 2, 2, rng);
            cb_dixon_patch_t P;
            cb_dixon_pencil_t D;
            cb_dixon_patch_init(P);
            cb_dixon_pencil_init(D);
            ok = implicitise(F, D, P, s, "phi: P");
            cb_nurbs_surface_eval(target, s, 0.25, 0.75);
            cb_dixon_pencil_clear(D);
            cb_dixon_patch_clear(P);
        }
        if (!ok)
            goto next;
        random_int_patch(q, 2, 3, rng);
        double at[3];
        cb_nurbs_surface_eval(at, q, 0.5, 0.25);
        for (int i = 0; i < q->n_u * q->n_v; i++)
            for (int c = 0; c < 3; c++)
                q->cw[4 * i + c] += target[c] - at[c]; /* weights are 1 */
        cb_dixon_patch_t Q;
        cb_dixon_patch_init(Q);
        CHECK(cb_dixon_patch_set_bezier(Q, q, &err) == CB_OK, "Q: %s", err.msg);
        cb_phi_t phi;
        cb_phi_init(phi);
        cb_status st = cb_phi_compute(phi, F, Q, &err);
        CHECK(st == CB_OK, "phi trial %d: %s", trial, err.msg);
        if (st == CB_OK) {
            CHECK(phi->ds == F->deg * 2 && phi->dt == F->deg * 3, "phi bidegree (%ld, %ld)",
                  (long)phi->ds, (long)phi->dt);
            fmpz_t v;
            fmpz_init(v);
            phi_at_dyadic(v, phi, 1, 1, 1, 2);
            CHECK(fmpz_is_zero(v), "trial %d (%s): phi(1/2, 1/4) != 0", trial,
                  analytic ? "analytic" : "Dixon");
            phi_at_dyadic(v, phi, 3, 3, 5, 4);
            CHECK(!fmpz_is_zero(v), "trial %d: phi(3/8, 5/16) = 0", trial);
            fmpz_clear(v);
            /* Bernstein form against exact values at dyadic points (k / 64, l / 64). */
            slong len = (phi->ds + 1) * (phi->dt + 1);
            double scale = max_abs(phi->bern, len), worst = 0.0, worst_pow = 0.0, l1 = 0.0;
            for (slong i = 0; i < len; i++)
                l1 += fabs(phi->cd[i]);
            int signs = 1;
            fmpz_t ex;
            fmpz_init(ex);
            for (int k = 0; k < 25; k++) {
                slong ns = check_rng_int(rng, 0, 64), nt = check_rng_int(rng, 0, 64);
                double sg = ns / 64.0, ta = nt / 64.0;
                phi_at_dyadic(ex, phi, ns, 6, nt, 6);
                slong x;
                double m = fmpz_get_d_2exp(&x, ex);
                double exact = ldexp(m, (int)(x - 6 * (phi->ds + phi->dt) - phi->exp));
                double a = phi_bern_eval(phi, sg, ta), b = cb_phi_eval_d(phi, sg, ta);
                double c = cb_phi_eval_direct_d(F, Q, sg, ta);
                worst = fmax(worst, fabs(a - exact) / scale);
                worst_pow = fmax(worst_pow, fabs(b - exact) / l1);
                if (fabs(exact) > 1e-6 * scale)
                    signs = signs && (exact > 0) == (c > 0);
            }
            fmpz_clear(ex);
            CHECK(worst < 1e-12, "trial %d: Bernstein form vs exact %g", trial, worst);
            CHECK(worst_pow < 1e-12, "trial %d: power form vs exact %g", trial, worst_pow);
            CHECK(signs, "trial %d: direct F(Q) differs in sign from phi", trial);
        }
        cb_phi_clear(phi);
        cb_dixon_patch_clear(Q);
    next:
        cb_implicit_clear(F);
        cb_nurbs_surface_clear(s);
        cb_nurbs_surface_clear(q);
    }
}

/* ---------------------------------------------------------------- inversion ---------------- */

/* Random rational graphs over [0, 1]^2 (no self-intersection), bicubic, then of bidegree (2, 2)
 * and (3, 2) (v of degree 2 takes the inversion's 2 x 2 resultant); sampled points come back
 * with their parameters, points moved off along the normal and points of the extension beyond
 * the box are not inside. */
static void test_inversion(check_rng *rng)
{
    int patches = 8, samples = 8;
    cb_inversion_params par;
    cb_inversion_params_default(&par);
    double worst = 0.0;
    for (int trial = 0; trial < patches; trial++) {
        int m = trial < 4 ? 3 : 2 + trial % 2, n = trial < 4 ? 3 : 2;
        double pts[48], w[16];
        for (int i = 0; i <= m; i++)
            for (int j = 0; j <= n; j++) {
                double *p = pts + 3 * ((n + 1) * i + j);
                p[0] = i / (double)m + check_rng_uniform(rng, -0.05, 0.05);
                p[1] = j / (double)n + check_rng_uniform(rng, -0.05, 0.05);
                p[2] = check_rng_uniform(rng, -0.3, 0.3);
                w[(n + 1) * i + j] = check_rng_uniform(rng, 0.7, 1.5);
            }
        cb_nurbs_surface_t s;
        cb_nurbs_surface_init(s);
        bezier(s, m, n, pts, w);
        cb_dixon_patch_t P;
        cb_dixon_pencil_t D;
        cb_dixon_patch_init(P);
        cb_dixon_pencil_init(D);
        cb_error err;
        cb_status st = cb_dixon_patch_set_bezier(P, s, &err);
        if (st == CB_OK)
            st = cb_dixon_pencil_set(D, P, &err);
        CHECK(st == CB_OK, "inversion patch %d: %s", trial, err.msg);
        cb_inversion_t res;
        cb_inversion_init(res);
        for (int k = 0; st == CB_OK && k < samples; k++) {
            double u = check_rng_uniform(rng, 0, 1), v = check_rng_uniform(rng, 0, 1), X[3];
            cb_nurbs_surface_eval(X, s, u, v);
            cb_status si = cb_inversion_solve(res, D, P, X, &par, &err);
            int found = 0, n_inside = 0;
            for (slong i = 0; i < res->n; i++)
                n_inside += res->pt[i].inside;
            for (slong i = 0; i < res->n; i++)
                if (res->pt[i].inside && fabs(res->pt[i].u - u) < 1e-9 &&
                    fabs(res->pt[i].v - v) < 1e-9)
                    found = 1;
            for (slong i = 0; i < res->n; i++)
                if (res->pt[i].inside)
                    worst = fmax(worst, fmax(fabs(res->pt[i].u - u), fabs(res->pt[i].v - v)));
            CHECK(n_inside == 1, "patch %d sample %d: %d preimages inside a graph patch", trial,
                  k, n_inside);
            CHECK(si == CB_OK && found && res->inside,
                  "patch %d sample %d: (%.15g, %.15g) not recovered (%ld solutions, first "
                  "(%.15g, %.15g))", trial, k, u, v, (long)res->n,
                  res->n ? res->pt[0].u : 0.0, res->n ? res->pt[0].v : 0.0);

            /* Off the surface: 0.05 along the normal. */
            double d[6][3], nrm[3];
            cb_nurbs_surface_eval_derivs(d, s, u, v);
            nrm[0] = d[1][1] * d[2][2] - d[1][2] * d[2][1];
            nrm[1] = d[1][2] * d[2][0] - d[1][0] * d[2][2];
            nrm[2] = d[1][0] * d[2][1] - d[1][1] * d[2][0];
            double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
            double Y[3];
            for (int c = 0; c < 3; c++)
                Y[c] = X[c] + 0.05 * nrm[c] / len;
            si = cb_inversion_solve(res, D, P, Y, &par, &err);
            CHECK(si == CB_OK && !res->inside, "patch %d sample %d: off-surface point inside",
                  trial, k);
        }
        /* On the extension beyond the box: found, but outside. */
        double X[3];
        cb_dixon_patch_eval(X, P, 1.15, 0.4);
        st = cb_inversion_solve(res, D, P, X, &par, &err);
        int found = 0;
        for (slong i = 0; i < res->n; i++)
            found |= fabs(res->pt[i].u - 1.15) < 1e-9 && fabs(res->pt[i].v - 0.4) < 1e-9;
        CHECK(st == CB_OK && found && !res->inside, "patch %d: extension point (1.15, 0.4): "
              "found %d inside %d", trial, found, res->inside);
        cb_inversion_clear(res);
        cb_dixon_pencil_clear(D);
        cb_dixon_patch_clear(P);
        cb_nurbs_surface_clear(s);
    }
    printf("inversion: worst parameter error %.2g\n", worst);
}

/* Bilinear patches (n = 1: the Dixon columns hold no v, so v comes from the moving planes):
 * rank 2, a quadric, and inversion of sampled points. */
static void test_bilinear(check_rng *rng)
{
    cb_inversion_params par;
    cb_inversion_params_default(&par);
    for (int trial = 0; trial < 4; trial++) {
        cb_nurbs_surface_t s;
        cb_nurbs_surface_init(s);
        random_int_patch(s, 1, 1, rng);
        cb_dixon_patch_t P;
        cb_dixon_pencil_t D;
        cb_implicit_t F;
        cb_dixon_patch_init(P);
        cb_dixon_pencil_init(D);
        cb_implicit_init(F);
        cb_error err;
        /* four random integer corners can be coplanar: that case is refused, skip it */
        int ok = cb_dixon_patch_set_bezier(P, s, &err) == CB_OK &&
                 cb_dixon_pencil_set(D, P, &err) == CB_OK;
        if (ok) {
            CHECK(cb_implicit_from_dixon(F, D, P, &err) == CB_OK, "bilinear: %s", err.msg);
            CHECK(F->deg == 2 && cb_dixon_pencil_rank(D) == 2, "bilinear trial %d: degree %ld",
                  trial, (long)F->deg);
            cb_inversion_t res;
            cb_inversion_init(res);
            for (int k = 0; k < 4; k++) {
                double u = check_rng_uniform(rng, 0, 1), v = check_rng_uniform(rng, 0, 1), X[3];
                cb_nurbs_surface_eval(X, s, u, v);
                cb_status st = cb_inversion_solve(res, D, P, X, &par, &err);
                int found = 0;
                for (slong i = 0; i < res->n; i++)
                    found |= res->pt[i].inside && fabs(res->pt[i].u - u) < 1e-9 &&
                             fabs(res->pt[i].v - v) < 1e-9;
                CHECK(st == CB_OK && found, "bilinear trial %d: (%g, %g) not recovered", trial,
                      u, v);
            }
            cb_inversion_clear(res);
        }
        cb_implicit_clear(F);
        cb_dixon_pencil_clear(D);
        cb_dixon_patch_clear(P);
        cb_nurbs_surface_clear(s);
    }
}

/* ---------------------------------------------------------------- degenerate input --------- */

static void test_degenerate(check_rng *rng)
{
    double pts[48];
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    cb_dixon_patch_t P;
    cb_dixon_pencil_t D;
    cb_dixon_patch_init(P);
    cb_dixon_pencil_init(D);
    cb_error err;
    for (int kind = 0; kind < 4; kind++) {
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++) {
                double *p = pts + 3 * (4 * i + j);
                for (int c = 0; c < 3; c++)
                    p[c] = check_rng_int(rng, -5, 5);
                if (kind == 0) /* a point */
                    p[0] = 1, p[1] = 2, p[2] = 3;
                if (kind == 1 && j > 0) /* a space curve: rows repeat the first column */
                    for (int c = 0; c < 3; c++)
                        p[c] = pts[3 * (4 * i) + c];
                if (kind >= 2) /* on the plane z = x/2 - y/4 + 1, tilted for kind 3 */
                    p[2] = kind == 2 ? 1.0 : p[0] / 2 - p[1] / 4 + 1;
            }
        bezier(s, 3, 3, pts, NULL);
        cb_status st = cb_dixon_patch_set_bezier(P, s, &err);
        CHECK(st == CB_OK, "degenerate %d: %s", kind, err.msg);
        st = cb_dixon_pencil_set(D, P, &err);
        const char *const point_parts[] = {"degenerate", "point", NULL};
        const char *const curve_parts[] = {"degenerate", "curve", NULL};
        const char *const plane_parts[] = {"planar", NULL};
        const char *const *parts = kind == 0 ? point_parts : kind == 1 ? curve_parts : plane_parts;
        cb_status want = kind < 2 ? CB_ERR_INVALID : CB_ERR_UNSUPPORTED;
        CHECK(st == want && check_msg_has(err.msg, parts), "degenerate %d: status %d, \"%s\"",
              kind, st, st == CB_OK ? "" : err.msg);
    }
    /* Non-finite control data and a multi-patch surface are refused. */
    double ku[10] = {0, 0, 0, 0, 0.5, 1, 1, 1, 1, 1}, kv[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    double big[60];
    for (int k = 0; k < 60; k++)
        big[k] = check_rng_uniform(rng, -1, 1);
    CHECK(cb_nurbs_surface_make(s, 3, 3, ku, 9, kv, 8, big, NULL, 5, 4, &err) == CB_OK,
          "two-span surface: %s", err.msg);
    CHECK(cb_dixon_patch_set_bezier(P, s, &err) == CB_ERR_INVALID, "two spans accepted");
    double hc[16] = {0};
    hc[0] = NAN;
    hc[12] = 1;
    const double box[4] = {0, 1, 0, 1};
    CHECK(cb_dixon_patch_set_power(P, 1, 1, hc, box, &err) == CB_ERR_INVALID, "NaN accepted");
    cb_dixon_pencil_clear(D);
    cb_dixon_patch_clear(P);
    cb_nurbs_surface_clear(s);
}

/* ---------------------------------------------------------------- choice ------------------- */

static void test_choose(check_rng *rng)
{
    cb_nurbs_surface_t a, b;
    cb_nurbs_surface_init(a);
    cb_nurbs_surface_init(b);
    quadric_patch(a, 0);
    random_int_patch(b, 2, 2, rng);
    cb_dixon_patch_t P, Q;
    cb_dixon_pencil_t DP, DQ;
    cb_dixon_patch_init(P);
    cb_dixon_patch_init(Q);
    cb_dixon_pencil_init(DP);
    cb_dixon_pencil_init(DQ);
    cb_error err;
    int ok = cb_dixon_patch_set_bezier(P, a, &err) == CB_OK &&
             cb_dixon_patch_set_bezier(Q, b, &err) == CB_OK &&
             cb_dixon_pencil_set(DP, P, &err) == CB_OK && cb_dixon_pencil_set(DQ, Q, &err) == CB_OK;
    CHECK(ok, "choose: %s", err.msg);
    if (ok) {
        CHECK(cb_implicit_choose(DP, DQ) == 0, "sphere patch not chosen over a biquadratic");
        CHECK(cb_implicit_choose(DQ, DP) == 1, "sphere patch not chosen (swapped)");
    }
    cb_dixon_pencil_clear(DP);
    cb_dixon_pencil_clear(DQ);
    cb_dixon_patch_clear(P);
    cb_dixon_patch_clear(Q);
    cb_nurbs_surface_clear(a);
    cb_nurbs_surface_clear(b);
}

int main(void)
{
    check_rng rng = {0x5d1c0de};
    test_example1();
    test_random_polynomial(&rng);
    test_sphere_torus();
    test_phi(&rng);
    test_inversion(&rng);
    test_bilinear(&rng);
    test_degenerate(&rng);
    test_choose(&rng);
    flint_cleanup();
    return check_report("test_ssi_dixon");
}
