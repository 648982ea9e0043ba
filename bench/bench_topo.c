/* bench_topo — time of the certified curve topology (ssi/curve_topo.h) against the bidegree of
 * phi.
 *
 * Usage: bench_topo [max_degree [coeff_bits [max_topology_degree]]]   (defaults 54, 16, 24)
 * For d = 6, 12, 16, 18, 24, 54 up to max_degree (the bidegrees of phi for a quadric, a torus
 * and a biquadratic patch against a bicubic one, and two bicubic patches, primer section 3): a
 * random dense phi of bidegree (d, d) with coeff_bits-bit coefficients, and up to
 * max_topology_degree a designed one (a product of d/2 circles in [0, 1]^2, bidegree (d, d))
 * whose counts are known from the circles' geometry and checked. Prints the time of the
 * modular resultant Res_t(phi, phi_t) the topology uses, of FLINT's fmpz_mpoly_resultant up
 * to d = 24 (and whether the two agree), and of the whole topology, which is run only up to
 * max_topology_degree (at (54, 54) it is impractical: cb_ctopo_opts has no time budget).
 * Not a ctest test. */
#define _POSIX_C_SOURCE 199309L /* clock_gettime under -std=c11 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "ssi/curve_topo.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void random_phi(fmpz_mpoly_t phi, slong d, flint_bitcnt_t bits, flint_rand_t state,
                       const fmpz_mpoly_ctx_t ctx)
{
    fmpz_t c;
    fmpz_init(c);
    fmpz_mpoly_zero(phi, ctx);
    for (slong i = 0; i <= d; i++)
        for (slong j = 0; j <= d; j++) {
            ulong e[2] = {(ulong)i, (ulong)j};
            fmpz_randtest(c, state, bits);
            fmpz_mpoly_set_coeff_fmpz_ui(phi, c, e, ctx);
        }
    fmpz_clear(c);
}

typedef struct {
    slong components, singular; /* -1: unknown */
} expected;

static slong uf_find(slong *parent, slong x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

/* prod_k (N s - a_k)^2 + (N t - b_k)^2 - r_k^2 with centres and radii in [0, 1] / N: circles
 * inside the box (centres in [0.2, 0.8], radii at most 0.2). Two of them cross at two points
 * when |r_i - r_j| < |c_i - c_j| < r_i + r_j (integers: exact); ex gets the components (union
 * of crossing pairs) and the crossings, or -1 when a pair touches or coincides. */
static void circles_phi(fmpz_mpoly_t phi, slong n, flint_rand_t state, expected *ex,
                        const fmpz_mpoly_ctx_t ctx)
{
    const slong N = 1000;
    slong ca[64], cb[64], cr[64], parent[64];
    fmpz_mpoly_t c, x;
    fmpz_mpoly_init(c, ctx);
    fmpz_mpoly_init(x, ctx);
    fmpz_mpoly_one(phi, ctx);
    for (slong k = 0; k < n; k++) {
        slong a = 200 + (slong)n_randint(state, 600), b = 200 + (slong)n_randint(state, 600);
        slong r = 50 + (slong)n_randint(state, 150);
        ca[k] = a;
        cb[k] = b;
        cr[k] = r;
        parent[k] = k;
        fmpz_mpoly_gen(x, 0, ctx);
        fmpz_mpoly_scalar_mul_si(x, x, N, ctx);
        fmpz_mpoly_sub_si(x, x, a, ctx);
        fmpz_mpoly_mul(c, x, x, ctx);
        fmpz_mpoly_gen(x, 1, ctx);
        fmpz_mpoly_scalar_mul_si(x, x, N, ctx);
        fmpz_mpoly_sub_si(x, x, b, ctx);
        fmpz_mpoly_mul(x, x, x, ctx);
        fmpz_mpoly_add(c, c, x, ctx);
        fmpz_mpoly_sub_si(c, c, r * r, ctx);
        fmpz_mpoly_mul(phi, phi, c, ctx);
    }
    fmpz_mpoly_clear(x, ctx);
    fmpz_mpoly_clear(c, ctx);
    ex->components = n;
    ex->singular = 0;
    for (slong i = 0; i < n; i++)
        for (slong j = i + 1; j < n; j++) {
            slong d2 = (ca[i] - ca[j]) * (ca[i] - ca[j]) + (cb[i] - cb[j]) * (cb[i] - cb[j]);
            slong lo = (cr[i] - cr[j]) * (cr[i] - cr[j]), hi = (cr[i] + cr[j]) * (cr[i] + cr[j]);
            if (d2 == lo || d2 == hi) {
                ex->components = ex->singular = -1;
                return;
            }
            if (lo < d2 && d2 < hi) {
                ex->singular += 2;
                slong a = uf_find(parent, i), b = uf_find(parent, j);
                if (a != b) {
                    parent[a] = b;
                    ex->components--;
                }
            }
        }
}

/* Res_t(phi, phi_t) by the modular resultant the topology uses and, up to d = 24, by FLINT's
 * fmpz_mpoly_resultant (checked equal); returns the modular time. */
static double run_resultant(slong d, const fmpz_mpoly_t phi, const fmpz_mpoly_ctx_t ctx)
{
    cb_bipoly_t p, q;
    fmpz_poly_t res;
    fmpz_mpoly_t pt, r;
    cb_bipoly_init(p);
    cb_bipoly_init(q);
    fmpz_poly_init(res);
    fmpz_mpoly_init(pt, ctx);
    fmpz_mpoly_init(r, ctx);
    double t0 = now();
    cb_bipoly_set_fmpz_mpoly(p, phi, ctx);
    cb_bipoly_resultant_dt(res, p);
    double t_res = now() - t0;
    printf("resultant %7.3f s", t_res);
    if (d <= 24) {
        t0 = now();
        fmpz_mpoly_derivative(pt, phi, 1, ctx);
        fmpz_mpoly_resultant(r, phi, pt, 1, ctx);
        double t_mpoly = now() - t0;
        cb_bipoly_set_fmpz_mpoly(q, r, ctx);
        int same = q->len == 0 ? fmpz_poly_is_zero(res) : fmpz_poly_equal(res, q->c);
        printf(" (fmpz_mpoly %7.3f s, %s)", t_mpoly, same ? "same" : "DIFFERENT");
    } else
        printf(" (fmpz_mpoly not run)        ");
    fmpz_mpoly_clear(r, ctx);
    fmpz_mpoly_clear(pt, ctx);
    fmpz_poly_clear(res);
    cb_bipoly_clear(q);
    cb_bipoly_clear(p);
    return t_res;
}

/* Returns the total time. */
static double run(const char *what, slong d, const fmpz_mpoly_t phi, const expected *ex,
                  slong topo_max, const fmpz_mpoly_ctx_t ctx)
{
    printf("%-8s (%2ld,%2ld)  ", what, (long)d, (long)d);
    double t_res = run_resultant(d, phi, ctx);
    if (d > topo_max) {
        printf("  topology not run (d > max_topology_degree %ld)\n", (long)topo_max);
        fflush(stdout);
        return t_res;
    }
    fmpq_t zero, one;
    cb_ctopo_opts opts;
    cb_ctopo_t T;
    cb_error err;
    fmpq_init(zero);
    fmpq_init(one);
    fmpq_one(one);
    cb_ctopo_opts_default(&opts);
    cb_ctopo_init(T);
    double t0 = now();
    cb_status st = cb_ctopo_compute(T, phi, ctx, zero, one, zero, one, &opts, &err);
    double t_topo = now() - t0;
    printf("  topology %8.3f s  ", t_topo);
    if (st == CB_OK) {
        printf("certified  lines %4ld components %3ld loops %3ld isolated %2ld singular %3ld",
               (long)T->n_lines, (long)T->n_components, (long)T->n_loops, (long)T->n_isolated,
               (long)T->n_singular);
        if (ex && ex->components >= 0)
            printf("  (%s: expected %ld, %ld)",
                   ex->components == T->n_components && ex->singular == T->n_singular
                       ? "ok"
                       : "WRONG",
                   (long)ex->components, (long)ex->singular);
        printf("\n");
    } else
        printf("%s: %s\n", cb_status_name(st), err.msg);
    fflush(stdout);
    cb_ctopo_clear(T);
    fmpq_clear(one);
    fmpq_clear(zero);
    return t_res + t_topo;
}

int main(int argc, char **argv)
{
    slong max_d = argc > 1 ? atol(argv[1]) : 54;
    flint_bitcnt_t bits = argc > 2 ? (flint_bitcnt_t)atol(argv[2]) : 16;
    slong topo_max = argc > 3 ? atol(argv[3]) : 24;
    static const slong degrees[] = {6, 12, 16, 18, 24, 54};
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_t phi;
    flint_rand_t state;
    expected ex;
    double total = 0.0;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    fmpz_mpoly_init(phi, ctx);
    flint_randinit(state);
    for (size_t i = 0; i < sizeof degrees / sizeof *degrees && degrees[i] <= max_d; i++) {
        slong d = degrees[i];
        random_phi(phi, d, bits, state, ctx);
        total += run("random", d, phi, NULL, topo_max, ctx);
        if (d > topo_max)
            continue;
        circles_phi(phi, d / 2, state, &ex, ctx);
        total += run("circles", d, phi, &ex, topo_max, ctx);
    }
    printf("total %.3f s\n", total);
    flint_randclear(state);
    fmpz_mpoly_clear(phi, ctx);
    fmpz_mpoly_ctx_clear(ctx);
    flint_cleanup();
    return 0;
}
