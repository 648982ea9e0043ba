/* bench_implicit — times of Dixon implicitisation and of phi = F(Q) construction (ssi/dixon.h,
 * ssi/implicit.h), exact and floating, for bicubic, biquadratic and analytic surfaces.
 *
 * Usage: bench_implicit [reps]   (reps of the cheap floating evaluations, default 100000)
 *
 * Patches are random rational Bezier patches with full double-precision data (53-bit
 * mantissas), the case a B-rep gives, plus bicubics with small integer data for comparison.
 * Exact columns: pencil = Dixon matrices, F = rank + minor + CRT + proof of F(P) = 0, phi =
 * F(Q) by CRT with Bernstein form. Floating columns: numerical rank of D(X) (complete
 * pivoting), F(X) from the scaled coefficients, phi(s, t) from its power form and F(Q(s, t))
 * directly, per evaluation. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "brep/analytic.h"
#include "ssi/dixon.h"
#include "ssi/implicit.h"

static double now(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static unsigned long long rng_state = 0x0123456789abcdefULL;

static double uniform(double lo, double hi)
{
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * (double)(rng_state >> 11) * 0x1.0p-53;
}

/* Random Bezier patch of degree (m, n) on [0, 1]^2: a wavy graph; integer data if ints. */
static int random_patch(cb_nurbs_surface_t s, int m, int n, int ints)
{
    double ku[2 * CB_MAX_BASIS], kv[2 * CB_MAX_BASIS], pts[3 * CB_MAX_BASIS * CB_MAX_BASIS],
        w[CB_MAX_BASIS * CB_MAX_BASIS];
    for (int i = 0; i <= m; i++) {
        ku[i] = 0.0;
        ku[m + 1 + i] = 1.0;
    }
    for (int j = 0; j <= n; j++) {
        kv[j] = 0.0;
        kv[n + 1 + j] = 1.0;
    }
    for (int i = 0; i <= m; i++)
        for (int j = 0; j <= n; j++) {
            double *p = pts + 3 * (i * (n + 1) + j);
            if (ints) {
                for (int c = 0; c < 3; c++)
                    p[c] = (double)(int)uniform(-5, 6);
                w[i * (n + 1) + j] = 1.0;
            } else {
                p[0] = (double)i / m + uniform(-0.05, 0.05);
                p[1] = (double)j / n + uniform(-0.05, 0.05);
                p[2] = uniform(-0.3, 0.3);
                w[i * (n + 1) + j] = uniform(0.7, 1.5);
            }
        }
    cb_error err;
    if (cb_nurbs_surface_make(s, m, n, ku, 2 * m + 2, kv, 2 * n + 2, pts, w, m + 1, n + 1,
                              &err) != CB_OK) {
        fprintf(stderr, "bench_implicit: %s\n", err.msg);
        return 0;
    }
    return 1;
}

/* Floating evaluation timings shared by all cases. */
static void bench_float(const cb_implicit_t F, const cb_dixon_patch_t Q, const cb_phi_t phi,
                        long reps)
{
    volatile double sink = 0.0;
    double t0 = now();
    for (long k = 0; k < reps; k++) {
        double X[3] = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
        sink += cb_implicit_eval_d(F, X);
    }
    double tF = (now() - t0) / (double)reps;
    t0 = now();
    for (long k = 0; k < reps; k++)
        sink += cb_phi_eval_d(phi, uniform(0, 1), uniform(0, 1));
    double tP = (now() - t0) / (double)reps;
    t0 = now();
    for (long k = 0; k < reps; k++)
        sink += cb_phi_eval_direct_d(F, Q, uniform(0, 1), uniform(0, 1));
    double tD = (now() - t0) / (double)reps;
    (void)sink;
    printf("    float: F(X) %.2f us, phi(s,t) power %.2f us, F(Q(s,t)) direct %.2f us\n",
           1e6 * tF, 1e6 * tP, 1e6 * tD);
}

static void bench_dixon(const char *name, int m, int n, int ints, int qm, int qn, long reps)
{
    cb_nurbs_surface_t s, q;
    cb_nurbs_surface_init(s);
    cb_nurbs_surface_init(q);
    cb_dixon_patch_t P, Q;
    cb_dixon_pencil_t D;
    cb_implicit_t F;
    cb_phi_t phi;
    cb_dixon_patch_init(P);
    cb_dixon_patch_init(Q);
    cb_dixon_pencil_init(D);
    cb_implicit_init(F);
    cb_phi_init(phi);
    cb_error err;
    if (!random_patch(s, m, n, ints) || !random_patch(q, qm, qn, ints))
        goto done;
    double t0 = now();
    cb_status st = cb_dixon_patch_set_bezier(P, s, &err);
    if (st == CB_OK)
        st = cb_dixon_pencil_set(D, P, &err);
    double t_pencil = now() - t0;
    t0 = now();
    if (st == CB_OK)
        st = cb_implicit_from_dixon(F, D, P, &err);
    double t_F = now() - t0;
    if (st == CB_OK)
        st = cb_dixon_patch_set_bezier(Q, q, &err);
    t0 = now();
    if (st == CB_OK)
        st = cb_phi_compute(phi, F, Q, &err);
    double t_phi = now() - t0;
    if (st != CB_OK) {
        printf("%-34s failed: %s\n", name, err.msg);
        goto done;
    }
    slong maxbits = 0;
    for (slong i = 0; i < cb_poly3_len((int)F->deg); i++)
        maxbits = FLINT_MAX(maxbits, (slong)fmpz_bits(F->c + i));
    printf("%-34s rank %2ld deg %2ld (%5ld-bit coeffs): pencil %.4f s, F %.3f s, "
           "phi (%ld,%ld) %.3f s\n", name, (long)cb_dixon_pencil_rank(D), (long)F->deg,
           (long)maxbits, t_pencil, t_F, (long)phi->ds, (long)phi->dt, t_phi);
    t0 = now();
    long nr = reps / 100 + 1;
    for (long k = 0; k < nr; k++) {
        double X[3] = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
        cb_dixon_pencil_rank_d(D, X, 1e-10);
    }
    printf("    float: numerical rank of D(X) %.2f us\n", 1e6 * (now() - t0) / (double)nr);
    bench_float(F, Q, phi, reps);
done:
    cb_phi_clear(phi);
    cb_implicit_clear(F);
    cb_dixon_pencil_clear(D);
    cb_dixon_patch_clear(P);
    cb_dixon_patch_clear(Q);
    cb_nurbs_surface_clear(s);
    cb_nurbs_surface_clear(q);
}

static void bench_analytic(const char *name, int torus, long reps)
{
    cb_frame fr;
    const double o[3] = {0.1, -0.2, 0.3}, ax[3] = {0.3, 0.4, 1.0};
    cb_analytic_surface a;
    cb_error err;
    cb_status st = cb_frame_make(&fr, o, ax, NULL, &err);
    if (st == CB_OK)
        st = torus ? cb_analytic_torus(&a, &fr, 1.0, 0.3, &err)
                   : cb_analytic_sphere(&a, &fr, 0.8, &err);
    cb_nurbs_surface_t q;
    cb_nurbs_surface_init(q);
    cb_dixon_patch_t Q;
    cb_implicit_t F;
    cb_phi_t phi;
    cb_dixon_patch_init(Q);
    cb_implicit_init(F);
    cb_phi_init(phi);
    double t0 = now();
    if (st == CB_OK)
        st = cb_implicit_from_analytic(F, &a, &err);
    double t_F = now() - t0;
    if (st == CB_OK && random_patch(q, 3, 3, 0))
        st = cb_dixon_patch_set_bezier(Q, q, &err);
    t0 = now();
    if (st == CB_OK)
        st = cb_phi_compute(phi, F, Q, &err);
    double t_phi = now() - t0;
    if (st != CB_OK) {
        printf("%-34s failed: %s\n", name, err.msg);
    } else {
        printf("%-34s deg %ld: F %.6f s, phi (%ld,%ld) %.3f s\n", name, (long)F->deg, t_F,
               (long)phi->ds, (long)phi->dt, t_phi);
        bench_float(F, Q, phi, reps);
    }
    cb_phi_clear(phi);
    cb_implicit_clear(F);
    cb_dixon_patch_clear(Q);
    cb_nurbs_surface_clear(q);
}

int main(int argc, char **argv)
{
    long reps = argc > 1 ? atol(argv[1]) : 100000;
    if (reps < 1)
        reps = 1;
    bench_dixon("bicubic, integer data, vs bicubic", 3, 3, 1, 3, 3, reps);
    bench_dixon("biquadratic, double data, vs biquad", 2, 2, 0, 2, 2, reps);
    bench_dixon("bicubic, double data, vs bicubic", 3, 3, 0, 3, 3, reps);
    bench_analytic("sphere vs bicubic (double data)", 0, reps);
    bench_analytic("torus vs bicubic (double data)", 1, reps);
    flint_cleanup();
    return 0;
}
