/* graph.c — graph pairs: two B-spline surfaces whose intersection is a designed curve
 * (cb_model_graph_pair, models.h). Every number is exact in binary, so the designed tangencies
 * (isolated contacts, curves of high-order contact) are tangencies of the surfaces as stored. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/models.h"

#define DEG CB_MODEL_POLY_DEG

/* ---------------------------------------------------------------- integer polynomials ------ */

cb_model_poly cb_model_poly_linear(long long a, long long b, long long c)
{
    cb_model_poly p;
    memset(&p, 0, sizeof p);
    p.c[1][0] = a;
    p.c[0][1] = b;
    p.c[0][0] = c;
    return p;
}

cb_model_poly cb_model_poly_mul(const cb_model_poly *a, const cb_model_poly *b)
{
    cb_model_poly p;
    memset(&p, 0, sizeof p);
    p.overflow = a->overflow || b->overflow;
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++) {
            if (!a->c[i][j])
                continue;
            for (int k = 0; k <= DEG; k++)
                for (int l = 0; l <= DEG; l++) {
                    long long v;
                    if (!b->c[k][l])
                        continue;
                    if (i + k > DEG || j + l > DEG ||
                        __builtin_mul_overflow(a->c[i][j], b->c[k][l], &v) ||
                        __builtin_add_overflow(p.c[i + k][j + l], v, &p.c[i + k][j + l]))
                        p.overflow = 1;
                }
        }
    return p;
}

cb_model_poly cb_model_poly_add(const cb_model_poly *a, const cb_model_poly *b, long long k)
{
    cb_model_poly p = *a;
    p.overflow = a->overflow || b->overflow;
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++) {
            long long v;
            if (__builtin_mul_overflow(k, b->c[i][j], &v) ||
                __builtin_add_overflow(p.c[i][j], v, &p.c[i][j]))
                p.overflow = 1;
        }
    return p;
}

cb_model_poly cb_model_poly_circle(long long a, long long b, long long c, long long r2)
{
    cb_model_poly x = cb_model_poly_linear(a, 0, -b), y = cb_model_poly_linear(0, a, -c);
    cb_model_poly xx = cb_model_poly_mul(&x, &x), yy = cb_model_poly_mul(&y, &y);
    cb_model_poly one = cb_model_poly_linear(0, 0, 1), s = cb_model_poly_add(&xx, &yy, 1);
    return cb_model_poly_add(&s, &one, -r2);
}

double cb_model_poly_eval(const cb_model_poly *p, double u, double v)
{
    double s = 0;
    for (int i = DEG; i >= 0; i--) {
        double r = 0;
        for (int j = DEG; j >= 0; j--)
            r = r * v + (double)p->c[i][j];
        s = s * u + r;
    }
    return s;
}

static void poly_degrees(int *du, int *dv, const cb_model_poly *p)
{
    *du = *dv = 0;
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++)
            if (p->c[i][j]) {
                *du = i > *du ? i : *du;
                *dv = j > *dv ? j : *dv;
            }
}

/* ---------------------------------------------------------------- exact Bernstein form ----- */

static long long fact(int n)
{
    return n <= 1 ? 1 : n * fact(n - 1);
}

static long long binom(int n, int k)
{
    return fact(n) / (fact(k) * fact(n - k));
}

/* Bernstein coefficients of p(s0 + ds a, b) of degree (m, n) on [0, 1]^2, times m! n!: integers,
 * out[k * (n + 1) + l]. Returns 0 when an intermediate overflows or a result leaves the range
 * where doubles are exact. */
static int bernstein(long long *out, const cb_model_poly *p, int m, int n, long long s0,
                     long long ds)
{
    long long q[DEG + 1][DEG + 1];
    memset(q, 0, sizeof q);
    for (int i = 0; i <= m; i++)
        for (int j = 0; j <= n; j++) {
            if (!p->c[i][j])
                continue;
            for (int a = 0; a <= i; a++) {
                long long v = binom(i, a);
                int bad = __builtin_mul_overflow(v, p->c[i][j], &v);
                for (int e = 0; e < i - a; e++)
                    bad |= __builtin_mul_overflow(v, s0, &v);
                for (int e = 0; e < a; e++)
                    bad |= __builtin_mul_overflow(v, ds, &v);
                if (bad || __builtin_add_overflow(q[a][j], v, &q[a][j]))
                    return 0;
            }
        }
    /* b_kl = sum C(k,i) C(l,j) q_ij / (C(m,i) C(n,j)), and m! / C(m,i) = i! (m - i)!. */
    for (int k = 0; k <= m; k++)
        for (int l = 0; l <= n; l++) {
            long long v = 0;
            for (int i = 0; i <= k; i++)
                for (int j = 0; j <= l; j++) {
                    long long w = binom(k, i) * binom(l, j) * fact(i) * fact(m - i) * fact(j) *
                                  fact(n - j);
                    if (__builtin_mul_overflow(w, q[i][j], &w) ||
                        __builtin_add_overflow(v, w, &v))
                        return 0;
                }
            if (llabs(v) >= (1LL << 53))
                return 0;
            out[k * (n + 1) + l] = v;
        }
    return 1;
}

/* ---------------------------------------------------------------- the pair ----------------- */

/* 16 f: f(u, v) = (u - 1/2)(v - 1/2) + (u - 1/2)^2 / 2 - (v - 1/2)^2 / 4, a biquadratic with
 * a saddle, so that P is curved in both directions. */
static cb_model_poly sixteen_f(void)
{
    cb_model_poly x = cb_model_poly_linear(2, 0, -1), y = cb_model_poly_linear(0, 2, -1);
    cb_model_poly xy = cb_model_poly_mul(&x, &y), xx = cb_model_poly_mul(&x, &x),
                  yy = cb_model_poly_mul(&y, &y), zero = cb_model_poly_linear(0, 0, 0);
    cb_model_poly s = cb_model_poly_add(&zero, &xy, 4);
    s = cb_model_poly_add(&s, &xx, 2);
    return cb_model_poly_add(&s, &yy, -1);
}

/* The rigid motion: the rotation (x, y, z) -> (z, x, y) (a third of a turn about (1, 1, 1)),
 * then a translation; both exact in binary. */
static const double MOVE[3] = {0.375, -1.25, 0.5};

/* Returns 0 when a sum was rounded. */
static int move(double out[3], const double X[3])
{
    double x = X[0], y = X[1], z = X[2];
    out[0] = z + MOVE[0];
    out[1] = x + MOVE[1];
    out[2] = y + MOVE[2];
    return out[0] - MOVE[0] == z && out[1] - MOVE[1] == x && out[2] - MOVE[2] == y;
}

void cb_model_graph_point(double X[3], const cb_model_graph *g, double u, double v)
{
    /* f directly (sixteen_f's polynomial over 16; test_models checks P against this). */
    double a = u - 0.5, b = v - 0.5, f = a * b + 0.5 * a * a - 0.25 * b * b;
    double Y[3] = {g->scale * u, g->scale * v, g->scale * f};
    (void)move(X, Y);
}

static void clamped(double *k, int deg, double a, double b)
{
    for (int i = 0; i <= deg; i++) {
        k[i] = a;
        k[deg + 1 + i] = b;
    }
}

/* Inserts the knot x once in direction dir of s (in place). */
static cb_status insert(cb_nurbs_surface_t s, cb_dir dir, double x, cb_error *err)
{
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    cb_status st = cb_nurbs_surface_insert_knot(t, s, dir, x, 1, err);
    if (st == CB_OK)
        st = cb_nurbs_surface_set(s, t, err);
    cb_nurbs_surface_clear(t);
    return st;
}

cb_status cb_model_graph_pair(cb_nurbs_surface_t P, cb_nurbs_surface_t Q, cb_model_graph *g,
                              const cb_model_poly *h, cb_error *err)
{
    if (h->overflow)
        return cb_error_set(err, CB_ERR_INVALID,
                            "graph pair: h overflowed 64-bit integers while it was built");
    int du, dv;
    poly_degrees(&du, &dv, h);
    /* Q's first parameter runs along y, its second along x. */
    int m = dv < 2 ? 2 : dv, n = du < 2 ? 2 : du;
    long long D = fact(m) * fact(n), odd = D;
    while (!(odd & 1))
        odd >>= 1;
    /* 2^-j h: |h| / 2^j <= 1/4 on the square, by the Bernstein bound. */
    long long NH[(DEG + 1) * (DEG + 1)], NG[(DEG + 1) * (DEG + 1)], NF[9];
    cb_model_poly hs;
    memset(&hs, 0, sizeof hs);
    for (int i = 0; i <= DEG; i++)
        for (int j = 0; j <= DEG; j++)
            hs.c[j][i] = h->c[i][j];
    if (!bernstein(NH, &hs, m, n, 1, -1))
        return cb_error_set(err, CB_ERR_INVALID,
                            "graph pair: h's Bernstein coefficients are not exact in doubles");
    long long big = 1;
    for (int k = 0; k < (m + 1) * (n + 1); k++)
        big = llabs(NH[k]) > big ? llabs(NH[k]) : big;
    int j = 2;
    while ((double)big / (double)D > ldexp(1, j - 2))
        j++;
    /* Q's height over (x, y): S (f + h / 2^j) = S (2^j 16 f + 16 h) / 2^(j + 4). */
    cb_model_poly F = sixteen_f(), G, Gs;
    for (int i = 0; i <= DEG; i++)
        for (int k = 0; k <= DEG; k++)
            F.c[i][k] = (long long)ldexp((double)F.c[i][k], j);
    G = cb_model_poly_add(&F, h, 16);
    memset(&Gs, 0, sizeof Gs);
    Gs.overflow = G.overflow;
    for (int i = 0; i <= DEG; i++)
        for (int k = 0; k <= DEG; k++)
            Gs.c[k][i] = G.c[i][k];
    if (G.overflow || !bernstein(NG, &Gs, m, n, 1, -1) || !bernstein(NF, &F, 2, 2, 0, 1))
        return cb_error_set(err, CB_ERR_INVALID,
                            "graph pair: Q's Bernstein coefficients are not exact in doubles");
    /* S: the odd part of D (it clears the odd denominators of k / m, l / n and of the
     * Bernstein coefficients), times a power of two bringing it into [1/2, 1). */
    int e2, e = 0;
    frexp((double)odd, &e2);
    while ((odd << e) != D)
        e++;
    double S = ldexp((double)odd, -e2);
    g->scale = S;
    g->height_shift = j;

    double *pq = malloc((size_t)(m + 1) * (n + 1) * 3 * sizeof(double)), pp[27];
    int exact = 1;
    if (!pq)
        return cb_error_set(err, CB_ERR_NOMEM, "graph pair: out of memory");
    for (int k = 0; k <= m; k++)
        for (int l = 0; l <= n; l++) {
            double Y[3] = {S * l / n, S * (m - k) / m,
                           ldexp((double)NG[k * (n + 1) + l], -e - e2 - j - 4)};
            exact &= move(pq + 3 * (k * (n + 1) + l), Y);
        }
    for (int k = 0; k <= 2; k++)
        for (int l = 0; l <= 2; l++) {
            /* NF holds 4 (2^j 16 f)'s Bernstein coefficients. */
            double Y[3] = {S * k / 2, S * l / 2, S * ldexp((double)NF[k * 3 + l], -j - 6)};
            exact &= move(pp + 3 * (k * 3 + l), Y);
        }
    double kp[6], kqs[2 * (DEG + 1)], kqt[2 * (DEG + 1)];
    clamped(kp, 2, 0, 1);
    clamped(kqs, m, 0, 2);
    clamped(kqt, n, -1, 1);
    cb_status st = exact ? CB_OK
                         : cb_error_set(err, CB_ERR_INVALID,
                                        "graph pair: a moved control point is not exact in "
                                        "doubles (h's coefficients are too long)");
    if (st == CB_OK)
        st = cb_nurbs_surface_make(P, 2, 2, kp, 6, kp, 6, pp, NULL, 3, 3, err);
    if (st == CB_OK)
        st = cb_nurbs_surface_make(Q, m, n, kqs, 2 * m + 2, kqt, 2 * n + 2, pq, NULL, m + 1,
                                   n + 1, err);
    free(pq);
    /* One interior knot per direction, at dyadic points: every ratio of knot differences that
     * insertion forms, here and when the SSI inserts the knot again to extract Bezier
     * patches, is then dyadic, so the nets and the patches stay exact (a second interior knot
     * would bring ratios such as 1/3). */
    if (st == CB_OK)
        st = insert(P, CB_DIR_U, CB_MODEL_GRAPH_KNOT_P[0], err);
    if (st == CB_OK)
        st = insert(P, CB_DIR_V, CB_MODEL_GRAPH_KNOT_P[1], err);
    if (st == CB_OK)
        st = insert(Q, CB_DIR_U, CB_MODEL_GRAPH_KNOT_Q[0], err);
    if (st == CB_OK)
        st = insert(Q, CB_DIR_V, CB_MODEL_GRAPH_KNOT_Q[1], err);
    return st;
}
