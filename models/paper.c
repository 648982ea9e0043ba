/* paper.c — the surface pair of the SSI paper's Example 2 (cb_model_paper_example2). */
#include <string.h>

#include "models/models.h"

/* Power coefficients: component q (x, y, z, w) of s^i t^j. Appendix A of
 * ../shared/reference/topology-guaranteed-ssi.md: P of Example 1, Q of Example 2. */
typedef struct {
    int q, i, j;
    long long c;
} term;

static const term P_TERMS[] = {
    {0, 3, 0, -32}, {0, 1, 2, 96},  {0, 2, 0, 48},  {0, 1, 1, -96}, {0, 0, 2, -48},
    {0, 1, 0, 6},   {0, 0, 1, 48},  {0, 0, 0, -11}, {1, 2, 1, 96},  {1, 0, 3, -32},
    {1, 2, 0, -48}, {1, 1, 1, -96}, {1, 0, 2, 48},  {1, 1, 0, 48},  {1, 0, 1, 6},
    {1, 0, 0, -11}, {2, 2, 0, 24},  {2, 0, 2, -24}, {2, 1, 0, -24}, {2, 0, 1, 24},
    {3, 0, 0, 2}};
static const term Q_TERMS[] = {{0, 1, 2, 2},  {0, 1, 0, 2},  {1, 2, 3, -1}, {1, 2, 0, 1},
                               {1, 0, 3, -3}, {1, 0, 0, 3},  {2, 3, 1, 2},  {2, 0, 1, 6},
                               {3, 2, 2, 1},  {3, 2, 0, 1},  {3, 0, 2, 1},  {3, 0, 0, 1}};

static const long long BINOM3[4] = {1, 3, 3, 1};

/* Bernstein coefficients of the cubic sum a[i] x^i over x = x0 + dx y, y in [0, 1], times
 * 3! = 6 (integers): out[k] = 6 sum_{i <= k} C(k, i) / C(3, i) b_i, with b the power
 * coefficients in y. */
static void bernstein3(long long out[4], const long long a[4], long long x0, long long dx)
{
    long long b[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4; i++) {
        /* a_i (x0 + dx y)^i */
        long long pw[4] = {1, 0, 0, 0};
        for (int e = 0; e < i; e++)
            for (int k = e + 1; k >= 0; k--)
                pw[k] = pw[k] * x0 + (k ? pw[k - 1] * dx : 0);
        for (int k = 0; k <= i; k++)
            b[k] += a[i] * pw[k];
    }
    static const long long C[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
    for (int k = 0; k < 4; k++) {
        out[k] = 0;
        for (int i = 0; i <= k; i++)
            out[k] += 6 / BINOM3[i] * C[k][i] * b[i];
    }
}

/* The rational bicubic patch of the terms over [s0, s0 + ds] x [t0, t0 + dt]: homogeneous
 * control points are the Bernstein coefficients times 36 (a factor common to all four
 * components leaves the surface as it is), integers, so exact in doubles. */
static cb_status patch(cb_nurbs_surface_t out, const term *t, int nt, long long s0, long long ds,
                       long long t0, long long dt, cb_error *err)
{
    cb_status st = cb_nurbs_surface_alloc(out, 3, 3, 4, 4, err);
    if (st != CB_OK)
        return st;
    for (int k = 0; k < 8; k++) {
        out->knots_u[k] = (double)(k < 4 ? s0 : s0 + ds);
        out->knots_v[k] = (double)(k < 4 ? t0 : t0 + dt);
    }
    for (int q = 0; q < 4; q++) {
        long long pc[4][4];
        memset(pc, 0, sizeof pc);
        for (int k = 0; k < nt; k++)
            if (t[k].q == q)
                pc[t[k].i][t[k].j] = t[k].c;
        /* In s for each power of t, then in t for each Bernstein index in s. */
        long long bs[4][4], bst[4][4];
        for (int j = 0; j < 4; j++) {
            long long col[4] = {pc[0][j], pc[1][j], pc[2][j], pc[3][j]}, o[4];
            bernstein3(o, col, s0, ds);
            for (int i = 0; i < 4; i++)
                bs[i][j] = o[i];
        }
        for (int i = 0; i < 4; i++)
            bernstein3(bst[i], bs[i], t0, dt);
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                out->cw[4 * (4 * i + j) + q] = (double)bst[i][j];
    }
    return cb_nurbs_surface_validate(out, err);
}

cb_status cb_model_paper_example2(cb_nurbs_surface_t P, cb_nurbs_surface_t Q, cb_error *err)
{
    cb_status st = patch(P, P_TERMS, (int)(sizeof P_TERMS / sizeof *P_TERMS), 0, 1, 0, 1, err);
    if (st == CB_OK)
        st = patch(Q, Q_TERMS, (int)(sizeof Q_TERMS / sizeof *Q_TERMS), -1, 2, 0, 2, err);
    return st;
}
