/* dixon.h — rational polynomial patches with exact integer coefficients and the Dixon matrix of
 * their moving planes (Yang, Jia, Yan, ACM TOG 2023, "Topology guaranteed B-spline
 * surface/surface intersection", sections 3 and 4.2; ssi-primer sections 1-2).
 *
 * A patch P(u, v) = (a, b, c, d) of bidegree (m, n) is kept in the power basis of its own
 * polynomial parameters with integer coefficients: every double is a dyadic rational, so one
 * power of two per patch turns the homogeneous control data into integers without rounding, and
 * scaling all four components by the same factor does not move the surface. For a Bezier patch
 * the polynomial parameters are the local ones, (u, v) in [0, 1]^2; the caller's parameter
 * domain is kept beside them and results are mapped back to it.
 *
 * The Dixon matrix of the moving planes f = d x - a w, g = d y - b w, h = d z - c w is, after
 * dropping a factor w^2, the linear pencil D(X) = x D1 + y D2 + z D3 + w D4 with
 * D1 = Dix(d, b, c), D2 = Dix(a, d, c), D3 = Dix(a, b, d), D4 = -Dix(a, b, c) (primer §2).
 * Dix(f, g, h) is the 2mn x 2mn coefficient matrix of the Dixon polynomial
 *   det | f(u,v) g(u,v) h(u,v) ; f(u,b) g(u,b) h(u,b) ; f(a,b) g(a,b) h(a,b) | / ((u-a)(v-b))
 * with rows indexed by a^i b^j (i < m, j < 2n; row i 2n + j) and columns by u^k v^l (k < 2m,
 * l < n; column k n + l), so that D(P(u, v)) U(u, v) = 0 for U = (u^k v^l) (Theorem 4.1). */
#ifndef CB_SSI_DIXON_H
#define CB_SSI_DIXON_H

#include <flint/fmpz.h>
#include <flint/fmpz_mat.h>

#include "brep/nurbs.h"
#include "brep/status.h"

/* ---------------------------------------------------------------- patches ------------------ */

typedef struct {
    slong m, n;       /* bidegree in u and v, >= 1 each */
    fmpz *coef;       /* 4 (m+1)(n+1) integers: component q (a, b, c, d) of u^i v^j at
                         q (m+1)(n+1) + i (n+1) + j */
    double *cd;       /* the same divided by a common power of two (|cd| <= 1), for evaluation */
    double box[4];    /* {u0, u1, v0, v1}: the part of the polynomial parameter plane the patch
                         covers ([0,1]^2 for a Bezier patch) */
    double domain[4]; /* the caller's parameter box that box maps to, affinely */
} cb_dixon_patch_struct;
typedef cb_dixon_patch_struct cb_dixon_patch_t[1];

void cb_dixon_patch_init(cb_dixon_patch_t P);
void cb_dixon_patch_clear(cb_dixon_patch_t P);

/* P from one rational Bezier patch s (n_u = deg_u + 1, n_v = deg_v + 1, as
 * cb_nurbs_surface_extract_bezier gives them). Method: the homogeneous control values are
 * scaled by one power of two to integers (exact, frexp), then converted from the Bernstein to
 * the power basis on [0, 1] in integers: coefficient of u^k v^l is
 *   sum_{i<=k, j<=l} b_ij C(m,k) C(k,i) (-1)^(k-i) C(n,l) C(l,j) (-1)^(l-j).
 * box = [0,1]^2, domain = s's parameter domain. Rejects non-finite data, a patch that is not a
 * single Bezier patch and degrees above CB_MAX_DEGREE. */
cb_status cb_dixon_patch_set_bezier(cb_dixon_patch_t P, const cb_nurbs_surface_t s,
                                    cb_error *err);

/* P from power-basis coefficients given as doubles: hc[q (m+1)(n+1) + i (n+1) + j] is the
 * coefficient of u^i v^j in component q of (a, b, c, d); box is the parameter box (also used as
 * domain). Converted exactly to integers by one power of two. Rejects non-finite values, an
 * empty box, d identically zero, m or n outside [1, CB_MAX_DEGREE]. */
cb_status cb_dixon_patch_set_power(cb_dixon_patch_t P, slong m, slong n, const double *hc,
                                   const double box[4], cb_error *err);

/* Euclidean point P(u, v) at polynomial parameters (u, v), any real values (outside the box
 * too, where a NURBS evaluator would clamp). Returns the homogeneous weight d(u, v) scaled as
 * cd; p is NaN-free only when that is non-zero. */
double cb_dixon_patch_eval(double p[3], const cb_dixon_patch_t P, double u, double v);

/* Maps polynomial parameters to the caller's domain. */
void cb_dixon_patch_to_domain(double *du, double *dv, const cb_dixon_patch_t P, double u,
                              double v);

/* ---------------------------------------------------------------- the Dixon pencil --------- */

typedef struct {
    slong m, n, size; /* size = 2 m n */
    fmpz_mat_t D[4];  /* D(X) = x D[0] + y D[1] + z D[2] + w D[3], exact integers */
    double *Dd;       /* 4 size^2 doubles: D[q] row-major at q size^2, divided by 2^dexp */
    slong dexp;
} cb_dixon_pencil_struct;
typedef cb_dixon_pencil_struct cb_dixon_pencil_t[1];

void cb_dixon_pencil_init(cb_dixon_pencil_t D);
void cb_dixon_pencil_clear(cb_dixon_pencil_t D);

/* Exact Dixon matrix of the scalar polynomials f, g, h of bidegree (m, n) (integer power-basis
 * coefficients, u^i v^j at i (n+1) + j), layout as in the file comment; out is resized to
 * 2mn x 2mn. Method: delta = -det(A, R, B) with A = (F(u,v) - F(u,b)) / (v - b), R = F(u,b),
 * B = (F(u,b) - F(a,b)) / (u - a) (row operations on the 3x3 determinant, so both divisions
 * are the exact divided differences of the monomials), expanded as A . (R x B) in dense
 * four-variate integer arrays. */
void cb_dixon_matrix(fmpz_mat_t out, const fmpz *f, const fmpz *g, const fmpz *h, slong m,
                     slong n);

/* The pencil of P. Checks first that P is a genuine surface, and refuses with a message that
 * says what it is instead:
 *   CB_ERR_INVALID      P collapses to a curve or a point: the 4 x 3 matrix (P, P_u, P_v) has
 *                       rank < 3 at two random parameter points modulo two random 62-bit
 *                       primes (rank 3 at one of them proves a surface);
 *   CB_ERR_UNSUPPORTED  P is planar: its homogeneous control coefficients span a space of
 *                       dimension <= 3 (exact rank), so every point lies on one plane L; then
 *                       D(X) = L(X) D' and D vanishes on the whole plane, which leaves no
 *                       implicit equation but L^(2mn) and no inversion — intersect with the
 *                       plane as an analytic surface instead. */
cb_status cb_dixon_pencil_set(cb_dixon_pencil_t D, const cb_dixon_patch_t P, cb_error *err);

/* Generic rank of the pencil over Q(x, y, z, w). Rule: rank of D(X) for a random integer X
 * modulo a random 62-bit prime, twice with independent primes and points, and the larger of the
 * two. Each value is a lower bound (a minor non-zero mod p at X is non-zero as a polynomial);
 * each equals the rank unless p divides the values of every maximal minor at X, which by
 * Schwartz-Zippel has probability <= size / p per trial. Points and primes come from a fixed
 * seed, so the answer is reproducible. */
slong cb_dixon_pencil_rank(const cb_dixon_pencil_t D);

/* Numerical rank of the rows x cols row-major matrix A (overwritten) by Gaussian elimination
 * with complete pivoting: the number of pivots with |pivot| > rel_tol * |first pivot| (the
 * largest entry). With rel_tol around 1e-10 it separates rank drops from round-off in matrices
 * built from data exact to double precision. */
slong cb_dixon_rank_d(double *A, slong rows, slong cols, double rel_tol);

/* Numerical rank of D(X) at the Euclidean point X (w = 1), with cb_dixon_rank_d. */
slong cb_dixon_pencil_rank_d(const cb_dixon_pencil_t D, const double X[3], double rel_tol);

/* D(X) in doubles at the Euclidean point X (w = 1), scaled by 2^-dexp: size^2, row-major. */
void cb_dixon_pencil_eval_d(double *M, const cb_dixon_pencil_t D, const double X[3]);

#endif
