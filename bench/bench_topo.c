/* bench_topo — time of the certified curve topology (ssi/topo.c) against the bidegree of phi.
 *
 * Usage: bench_topo [max_degree [coeff_bits]]   (defaults 18 and 16)
 * For d = 6, 12, 18, ... up to max_degree: a random dense phi of bidegree (d, d) with
 * coeff_bits-bit coefficients, and a designed one (a product of d/2 circles in [0, 1]^2,
 * bidegree (d, d)). Prints the time of the resultant alone and of the whole topology, and the
 * counts. Not a ctest test: bidegree 24 random curves take minutes. */
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

/* prod_k (N s - a_k)^2 + (N t - b_k)^2 - r_k^2 with centres and radii in [0, 1] / N. */
static void circles_phi(fmpz_mpoly_t phi, slong n, flint_rand_t state, const fmpz_mpoly_ctx_t ctx)
{
    const slong N = 1000;
    fmpz_mpoly_t c, x;
    fmpz_mpoly_init(c, ctx);
    fmpz_mpoly_init(x, ctx);
    fmpz_mpoly_one(phi, ctx);
    for (slong k = 0; k < n; k++) {
        slong a = 200 + (slong)n_randint(state, 600), b = 200 + (slong)n_randint(state, 600);
        slong r = 50 + (slong)n_randint(state, 150);
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
}

static void run(const char *what, slong d, const fmpz_mpoly_t phi, const fmpz_mpoly_ctx_t ctx)
{
    fmpq_t zero, one;
    cb_ctopo_opts opts;
    cb_ctopo_t T;
    cb_error err;
    fmpz_mpoly_t pt, r;
    fmpq_init(zero);
    fmpq_init(one);
    fmpq_one(one);
    fmpz_mpoly_init(pt, ctx);
    fmpz_mpoly_init(r, ctx);
    cb_ctopo_opts_default(&opts);
    cb_ctopo_init(T);

    double t0 = now();
    fmpz_mpoly_derivative(pt, phi, 1, ctx);
    fmpz_mpoly_resultant(r, phi, pt, 1, ctx);
    double t_res = now() - t0;
    t0 = now();
    cb_status st = cb_ctopo_compute(T, phi, ctx, zero, one, zero, one, &opts, &err);
    double t_topo = now() - t0;
    printf("%-8s (%2ld,%2ld)  resultant %8.3f s  topology %8.3f s  ", what, (long)d, (long)d,
           t_res, t_topo);
    if (st == CB_OK)
        printf("lines %4ld components %3ld loops %3ld isolated %2ld singular %3ld\n",
               (long)T->n_lines, (long)T->n_components, (long)T->n_loops, (long)T->n_isolated,
               (long)T->n_singular);
    else
        printf("%s: %s\n", cb_status_name(st), err.msg);
    fflush(stdout);
    cb_ctopo_clear(T);
    fmpz_mpoly_clear(r, ctx);
    fmpz_mpoly_clear(pt, ctx);
    fmpq_clear(one);
    fmpq_clear(zero);
}

int main(int argc, char **argv)
{
    slong max_d = argc > 1 ? atol(argv[1]) : 18;
    flint_bitcnt_t bits = argc > 2 ? (flint_bitcnt_t)atol(argv[2]) : 16;
    fmpz_mpoly_ctx_t ctx;
    fmpz_mpoly_t phi;
    flint_rand_t state;
    fmpz_mpoly_ctx_init(ctx, 2, ORD_LEX);
    fmpz_mpoly_init(phi, ctx);
    flint_randinit(state);
    for (slong d = 6; d <= max_d; d += 6) {
        random_phi(phi, d, bits, state, ctx);
        run("random", d, phi, ctx);
        circles_phi(phi, d / 2, state, ctx);
        run("circles", d, phi, ctx);
    }
    flint_randclear(state);
    fmpz_mpoly_clear(phi, ctx);
    fmpz_mpoly_ctx_clear(ctx);
    flint_cleanup();
    return 0;
}
