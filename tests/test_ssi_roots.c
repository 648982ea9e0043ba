/* Exact real-root isolation (ssi/roots.c): known rational roots, irrational roots, clusters,
 * multiplicities, roots on end points and subdivision points, and agreement with Arb. */
#include <math.h>

#include <acb.h>
#include <arb_fmpz_poly.h>

#include "check.h"
#include "ssi/roots.h"

/* Does root k of r hold x (closed if exact, open otherwise)? */
static int holds(const cb_roots_t r, slong k, const fmpq_t x)
{
    const cb_root_interval_struct *iv = &r->root[k];
    if (fmpq_equal(iv->lo, iv->hi))
        return fmpq_equal(iv->lo, x);
    return fmpq_cmp(iv->lo, x) < 0 && fmpq_cmp(x, iv->hi) < 0;
}

/* Sorted, pairwise disjoint, end points not roots of the squarefree part. */
static int well_formed(const cb_roots_t r)
{
    fmpq_t v;
    fmpq_init(v);
    int ok = 1;
    for (slong k = 0; k < r->n && ok; k++) {
        const cb_root_interval_struct *iv = &r->root[k];
        ok = fmpq_cmp(iv->lo, iv->hi) <= 0;
        if (k > 0)
            ok = ok && fmpq_cmp(r->root[k - 1].hi, iv->lo) <= 0 &&
                 fmpq_cmp(r->root[k - 1].lo, iv->lo) < 0;
        if (ok && !fmpq_equal(iv->lo, iv->hi)) {
            fmpz_poly_evaluate_fmpq(v, r->sqfree, iv->lo);
            ok = !fmpq_is_zero(v);
            fmpz_poly_evaluate_fmpq(v, r->sqfree, iv->hi);
            ok = ok && !fmpq_is_zero(v);
        }
    }
    fmpq_clear(v);
    return ok;
}

/* p *= (den x - num)^mult */
static void mul_linear(fmpz_poly_t p, slong num, slong den, int mult)
{
    fmpz_poly_t f;
    fmpz_poly_init(f);
    fmpz_poly_set_coeff_si(f, 0, -num);
    fmpz_poly_set_coeff_si(f, 1, den);
    for (int m = 0; m < mult; m++)
        fmpz_poly_mul(p, p, f);
    fmpz_poly_clear(f);
}

static void test_random_rational_roots(check_rng *rng)
{
    for (int t = 0; t < 300; t++) {
        fmpz_poly_t p;
        fmpz_poly_init(p);
        fmpz_poly_set_si(p, check_rng_int(rng, 1, 5) * (check_rng_int(rng, 0, 1) ? 1 : -1));
        int m = check_rng_int(rng, 0, 8);
        slong num[8], den[8];
        for (int i = 0; i < m; i++) {
            den[i] = check_rng_int(rng, 1, 12);
            num[i] = check_rng_int(rng, -3 * (int)den[i], 3 * (int)den[i]);
            mul_linear(p, num[i], den[i], check_rng_int(rng, 1, 3));
        }
        /* A factor with no real root: x^2 + c. */
        if (check_rng_int(rng, 0, 1)) {
            fmpz_poly_t q;
            fmpz_poly_init(q);
            fmpz_poly_set_coeff_si(q, 2, 1);
            fmpz_poly_set_coeff_si(q, 0, check_rng_int(rng, 1, 9));
            fmpz_poly_mul(p, p, q);
            fmpz_poly_clear(q);
        }
        fmpq_t a, b, x;
        fmpq_init(a);
        fmpq_init(b);
        fmpq_init(x);
        fmpq_set_si(a, check_rng_int(rng, -40, 10), (ulong)check_rng_int(rng, 1, 12));
        fmpq_set_si(b, check_rng_int(rng, 11, 40), (ulong)check_rng_int(rng, 1, 12));
        if (fmpq_cmp(a, b) >= 0)
            fmpq_add_si(b, a, 1);
        /* Expected: the distinct known roots inside [a, b]. */
        int expected = 0;
        for (int i = 0; i < m; i++) {
            int dup = 0;
            for (int j = 0; j < i; j++)
                dup |= num[i] * den[j] == num[j] * den[i];
            fmpq_set_si(x, num[i], (ulong)den[i]);
            if (!dup && fmpq_cmp(a, x) <= 0 && fmpq_cmp(x, b) <= 0)
                expected++;
        }
        cb_roots_t r;
        cb_roots_init(r);
        cb_status st = cb_roots_isolate(r, p, a, b, NULL);
        CHECK(st == CB_OK && r->n == expected, "trial %d: %ld roots, %d expected", t, (long)r->n,
              expected);
        CHECK(well_formed(r), "trial %d: intervals not sorted/disjoint/clean", t);
        for (int i = 0; i < m; i++) {
            fmpq_set_si(x, num[i], (ulong)den[i]);
            if (fmpq_cmp(a, x) > 0 || fmpq_cmp(x, b) > 0)
                continue;
            int count = 0;
            for (slong k = 0; k < r->n; k++)
                count += holds(r, k, x);
            CHECK(count == 1, "trial %d: root %ld/%ld held by %d intervals", t, (long)num[i],
                  (long)den[i], count);
        }
        cb_roots_clear(r);
        fmpq_clear(x);
        fmpq_clear(b);
        fmpq_clear(a);
        fmpz_poly_clear(p);
    }
}

static void test_arb_agreement(check_rng *rng)
{
    for (int t = 0; t < 100; t++) {
        fmpz_poly_t p;
        fmpz_poly_init(p);
        int deg = check_rng_int(rng, 1, 24);
        for (int i = 0; i <= deg; i++)
            fmpz_poly_set_coeff_si(p, i, check_rng_int(rng, -1000, 1000));
        if (fmpz_poly_degree(p) < 1)
            fmpz_poly_set_coeff_si(p, 1, 1);
        /* Cauchy's bound: every real root lies in [-B, B]. */
        fmpz_t B, c;
        fmpz_init(B);
        fmpz_init(c);
        for (slong i = 0; i < fmpz_poly_degree(p); i++) {
            fmpz_abs(c, p->coeffs + i);
            if (fmpz_cmp(c, B) > 0)
                fmpz_set(B, c);
        }
        fmpz_add_ui(B, B, 1);
        fmpq_t a, b;
        fmpq_init(a);
        fmpq_init(b);
        fmpq_set_fmpz_frac(b, B, fmpz_poly_lead(p));
        fmpq_abs(b, b);
        fmpq_add_si(b, b, 1);
        fmpq_neg(a, b);
        cb_roots_t r;
        cb_roots_init(r);
        cb_roots_isolate(r, p, a, b, NULL);

        slong d = fmpz_poly_degree(r->sqfree);
        acb_ptr z = _acb_vec_init(d);
        arb_fmpz_poly_complex_roots(z, r->sqfree, 0, 64);
        slong real = 0;
        for (slong i = 0; i < d; i++)
            real += arb_is_zero(acb_imagref(z + i));
        CHECK(real == r->n, "trial %d: %ld real roots by Arb, %ld isolated", t, (long)real,
              (long)r->n);
        /* Arb lists the real roots first, in increasing order: each must sit in ours. */
        for (slong i = 0; i < real && real == r->n; i++) {
            cb_roots_refine(r, i, (fmpq_t){{1, 1LL << 40}});
            double mid = cb_roots_mid_d(r, i), want = arf_get_d(arb_midref(acb_realref(z + i)),
                                                                ARF_RND_NEAR);
            CHECK(fabs(mid - want) <= 1e-9 * fmax(1.0, fabs(want)),
                  "trial %d root %ld: ours %.17g, Arb %.17g", t, (long)i, mid, want);
        }
        CHECK(well_formed(r), "trial %d: intervals not clean after refinement", t);
        _acb_vec_clear(z, d);
        cb_roots_clear(r);
        fmpq_clear(a);
        fmpq_clear(b);
        fmpz_clear(B);
        fmpz_clear(c);
        fmpz_poly_clear(p);
    }
}

/* Plain bisection with rational evaluation: what cb_roots_refine must give, interval for
 * interval. */
static void reference_refine(fmpq_t lo, fmpq_t hi, const fmpz_poly_t p, const fmpq_t width)
{
    fmpq_t w, mid, val;
    fmpq_init(w);
    fmpq_init(mid);
    fmpq_init(val);
    fmpz_poly_evaluate_fmpq(val, p, lo);
    int sign_lo = fmpq_sgn(val);
    fmpq_sub(w, hi, lo);
    while (fmpq_cmp(w, width) > 0) {
        fmpq_add(mid, lo, hi);
        fmpq_div_2exp(mid, mid, 1);
        fmpz_poly_evaluate_fmpq(val, p, mid);
        int s = fmpq_sgn(val);
        if (s == 0) {
            fmpq_set(lo, mid);
            fmpq_set(hi, mid);
            break;
        }
        if (s == sign_lo)
            fmpq_set(lo, mid);
        else
            fmpq_set(hi, mid);
        fmpq_div_2exp(w, w, 1);
    }
    fmpq_clear(val);
    fmpq_clear(mid);
    fmpq_clear(w);
}

/* cb_roots_refine takes the steps of plain bisection (its midpoints' signs by integer Horner):
 * the same intervals, exact hits included, on non-dyadic end points and widths, refined in one
 * call or in several. Roots k / 2^j and k / 3 make subdivision points and non-dyadic ones. */
static void test_refine_matches_bisection(check_rng *rng)
{
    int hits = 0; /* roots hit exactly by a midpoint, 8 or more steps in */
    for (int t = 0; t < 300; t++) {
        fmpz_poly_t p;
        fmpz_poly_init(p);
        fmpz_poly_set_si(p, check_rng_int(rng, 1, 9));
        int nf = (int)check_rng_int(rng, 1, 6);
        for (int f = 0; f < nf; f++) {
            if (check_rng_int(rng, 0, 2) == 0) {
                /* x^2 - c: irrational roots */
                fmpz_poly_t q;
                fmpz_poly_init(q);
                fmpz_poly_set_coeff_si(q, 2, 1);
                fmpz_poly_set_coeff_si(q, 0, -check_rng_int(rng, 2, 50));
                fmpz_poly_mul(p, p, q);
                fmpz_poly_clear(q);
            } else {
                slong den = check_rng_int(rng, 0, 1) ? 3 : (WORD(1) << check_rng_int(rng, 0, 12));
                mul_linear(p, check_rng_int(rng, -5 * (int)den, 5 * (int)den), den,
                           (int)check_rng_int(rng, 1, 2));
            }
        }
        fmpq_t a, b, w, lo, hi;
        fmpq_init(a);
        fmpq_init(b);
        fmpq_init(w);
        fmpq_init(lo);
        fmpq_init(hi);
        /* Integer ends half the time, so that dyadic roots can fall on midpoints. */
        int dyadic = t % 2;
        fmpq_set_si(a, -check_rng_int(rng, 1, 200), dyadic ? 1 : (ulong)check_rng_int(rng, 1, 7));
        fmpq_set_si(b, check_rng_int(rng, 1, 200), dyadic ? 1 : (ulong)check_rng_int(rng, 1, 7));
        cb_roots_t r;
        cb_roots_init(r);
        cb_roots_isolate(r, p, a, b, NULL);
        for (slong k = 0; k < r->n; k++) {
            for (int pass = 0; pass < 2; pass++) {
                fmpq_set_si(w, 1, (ulong)check_rng_int(rng, 1, 5));
                fmpq_div_2exp(w, w, (ulong)check_rng_int(rng, 0, pass ? 90 : 20));
                fmpq_set(lo, r->root[k].lo);
                fmpq_set(hi, r->root[k].hi);
                /* An exact hit after at least 8 steps: cb_roots_refine's guessed cell. */
                fmpq_t steps;
                fmpq_init(steps);
                fmpq_sub(steps, hi, lo);
                fmpq_div(steps, steps, w);
                int open = fmpq_cmp_ui(steps, 256) >= 0;
                fmpq_clear(steps);
                reference_refine(lo, hi, r->sqfree, w);
                cb_roots_refine(r, k, w);
                CHECK(fmpq_equal(lo, r->root[k].lo) && fmpq_equal(hi, r->root[k].hi),
                      "trial %d root %ld pass %d: refinement differs from bisection", t,
                      (long)k, pass);
                hits += open && fmpq_equal(lo, hi);
            }
        }
        CHECK(well_formed(r), "trial %d: intervals not clean after refinement", t);
        cb_roots_clear(r);
        fmpq_clear(a);
        fmpq_clear(b);
        fmpq_clear(w);
        fmpq_clear(lo);
        fmpq_clear(hi);
        fmpz_poly_clear(p);
    }
    CHECK(hits > 0, "no root was hit exactly by a bisection midpoint 8 steps in");
}

static void test_special_cases(void)
{
    fmpz_poly_t p;
    fmpq_t a, b, x, w;
    cb_roots_t r;
    fmpz_poly_init(p);
    fmpq_init(a);
    fmpq_init(b);
    fmpq_init(x);
    fmpq_init(w);
    cb_roots_init(r);

    /* x (x - 1) (2x - 1) (4x - 1) (7x - 5) on [0, 1]: the end points and the subdivision
     * points 1/2, 1/4 are hit exactly; 5/7 gets an interval that does not end on 1/2. */
    fmpz_poly_set_ui(p, 1);
    mul_linear(p, 0, 1, 1);
    mul_linear(p, 1, 1, 1);
    mul_linear(p, 1, 2, 1);
    mul_linear(p, 1, 4, 1);
    mul_linear(p, 5, 7, 1);
    fmpq_set_si(a, 0, 1);
    fmpq_set_si(b, 1, 1);
    cb_roots_isolate(r, p, a, b, NULL);
    CHECK(r->n == 5 && well_formed(r), "x(x-1)(2x-1)(4x-1)(7x-5): %ld roots", (long)r->n);
    static const slong want_num[5] = {0, 1, 1, 5, 1}, want_den[5] = {1, 4, 2, 7, 1};
    for (slong k = 0; k < r->n && k < 5; k++) {
        fmpq_set_si(x, want_num[k], (ulong)want_den[k]);
        CHECK(holds(r, k, x), "x(x-1)(2x-1)(4x-1)(7x-5): root %ld misplaced", (long)k);
        CHECK(fmpq_equal(r->root[k].lo, r->root[k].hi) == (k != 3),
              "x(x-1)(2x-1)(4x-1)(7x-5): root %ld exact/open wrong", (long)k);
    }

    /* Multiple roots count once: (3x - 1)^3 (5x + 1)^2 on [-1, 1]. */
    fmpz_poly_set_ui(p, 1);
    mul_linear(p, 1, 3, 3);
    mul_linear(p, -1, 5, 2);
    fmpq_set_si(a, -1, 1);
    cb_roots_isolate(r, p, a, b, NULL);
    CHECK(r->n == 2 && fmpz_poly_degree(r->sqfree) == 2, "multiple roots: %ld roots, deg %ld",
          (long)r->n, (long)fmpz_poly_degree(r->sqfree));

    /* A cluster 1e-12 apart: (3x - 1)(3e12 x - 1e12 - 3), roots 1/3 and 1/3 + 1e-12. */
    fmpz_poly_set_ui(p, 1);
    mul_linear(p, 1, 3, 1);
    mul_linear(p, 1000000000003LL, 3000000000000LL, 1);
    fmpq_set_si(a, 0, 1);
    cb_roots_isolate(r, p, a, b, NULL);
    CHECK(r->n == 2 && well_formed(r), "cluster: %ld roots", (long)r->n);
    if (r->n == 2) {
        fmpq_set_si(x, 1, 3);
        CHECK(holds(r, 0, x), "cluster: 1/3 not in the first interval");
        fmpq_set_si(x, 1000000000003LL, 3000000000000ULL);
        CHECK(holds(r, 1, x), "cluster: 1/3 + 1e-12 not in the second interval");
    }

    /* sqrt(2) refined to 2^-60. */
    fmpz_poly_zero(p);
    fmpz_poly_set_coeff_si(p, 2, 1);
    fmpz_poly_set_coeff_si(p, 0, -2);
    fmpq_set_si(b, 2, 1);
    cb_roots_isolate(r, p, a, b, NULL);
    CHECK(r->n == 1, "x^2 - 2 on [0, 2]: %ld roots", (long)r->n);
    if (r->n == 1) {
        fmpq_one(w);
        fmpq_div_2exp(w, w, 60);
        cb_roots_refine(r, 0, w);
        fmpq_sub(x, r->root[0].hi, r->root[0].lo);
        CHECK(fmpq_cmp(x, w) <= 0 && fabs(cb_roots_mid_d(r, 0) - sqrt(2.0)) <= 4e-16,
              "sqrt 2 refined to %.17g", cb_roots_mid_d(r, 0));
    }

    /* Wilkinson's polynomial: 20 roots on [0, 21]. */
    fmpz_poly_set_ui(p, 1);
    for (int k = 1; k <= 20; k++)
        mul_linear(p, k, 1, 1);
    fmpq_set_si(b, 21, 1);
    cb_roots_isolate(r, p, a, b, NULL);
    CHECK(r->n == 20 && well_formed(r), "Wilkinson: %ld roots", (long)r->n);
    for (slong k = 0; k < r->n; k++) {
        fmpq_set_si(x, k + 1, 1);
        CHECK(holds(r, k, x), "Wilkinson: root %ld misplaced", (long)(k + 1));
    }

    /* Constants have no roots; zero polynomial and empty intervals are refused. */
    fmpz_poly_set_si(p, -7);
    CHECK(cb_roots_isolate(r, p, a, b, NULL) == CB_OK && r->n == 0, "constant: %ld roots",
          (long)r->n);
    cb_error err;
    fmpz_poly_zero(p);
    CHECK(cb_roots_isolate(r, p, a, b, &err) == CB_ERR_INVALID && strstr(err.msg, "zero"),
          "zero polynomial accepted");
    fmpz_poly_set_coeff_si(p, 1, 1);
    CHECK(cb_roots_isolate(r, p, b, a, &err) == CB_ERR_INVALID && strstr(err.msg, "empty"),
          "reversed interval accepted");
    CHECK(cb_roots_isolate(r, p, a, a, &err) == CB_ERR_INVALID, "point interval accepted");

    cb_roots_clear(r);
    fmpq_clear(w);
    fmpq_clear(x);
    fmpq_clear(b);
    fmpq_clear(a);
    fmpz_poly_clear(p);
}

int main(void)
{
    check_rng rng = {2023};
    test_random_rational_roots(&rng);
    test_arb_agreement(&rng);
    test_refine_matches_bisection(&rng);
    test_special_cases();
    flint_cleanup_master();
    return check_report("ssi_roots");
}
