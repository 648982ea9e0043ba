/* implicit.h — exact implicit equations F of patches and analytic surfaces, and the
 * substitution phi(s, t) = F(Q(s, t)) of another patch (Yang, Jia, Yan, ACM TOG 2023, section
 * 4.2, Proposition 1, Remark 1, footnote 1, equation (12); ssi-primer sections 2-4).
 *
 * F is homogeneous of degree N in (x, y, z, w), stored densely with the cb_poly3 index layout
 * (brep/analytic.h): c[cb_poly3_index(i, j, k)] multiplies x^i y^j z^k w^(N-i-j-k). Read with
 * w = 1 it is the dehomogenised equation in Euclidean coordinates, and a cb_poly3 of degree N is
 * exactly this layout. F is primitive (content 1) with its first non-zero coefficient in that
 * order positive, so two computations of the same surface give the same integers.
 *
 * Every modular computation here ends in a proof, not a guess: values are reconstructed by CRT
 * over 62-bit primes until the product of the primes exceeds twice an a-priori bound on the
 * coefficients (product of row 1-norms for determinants, 1-norm products for substitutions). */
#ifndef CB_SSI_IMPLICIT_H
#define CB_SSI_IMPLICIT_H

#include <flint/fmpz.h>
#include <flint/fmpz_mpoly.h>

#include "brep/analytic.h"
#include "ssi/dixon.h"

/* ---------------------------------------------------------------- implicit equations ------- */

typedef struct {
    slong deg;   /* total degree N; -1 when unset */
    fmpz *c;     /* cb_poly3_len(N) integers, layout above */
    double *cd;  /* c 2^-exp, |cd| <= 1, for floating evaluation */
    slong exp;
    slong rank;  /* rank of the Dixon pencil used (degree of the minor), 0 for an analytic F */
    int factored; /* 1 if F was split off a minor by factorisation (base points) */
} cb_implicit_struct;
typedef cb_implicit_struct cb_implicit_t[1];

void cb_implicit_init(cb_implicit_t F);
void cb_implicit_clear(cb_implicit_t F);
void cb_implicit_swap(cb_implicit_t F, cb_implicit_t G);

/* Implicit equation of the patch P from its Dixon pencil D (cb_dixon_pencil_set(D, P)).
 * Method (Prop. 1, Remark 1): r = cb_dixon_pencil_rank(D). If r = 2mn (no base points) F is
 * det D(X); otherwise a maximal minor is chosen by pivoted elimination of D at a random point
 * modulo a prime (non-zero there, hence non-zero), and F is the irreducible factor of it that
 * vanishes on P (fmpz_mpoly_factor; the others are extraneous, from base points). The
 * determinant or minor, homogeneous of degree r, is interpolated modulo primes from its values
 * at the points (x_i, y_j, z_k, 1), i + j + k <= r, of a tensor grid (multivariate Newton
 * divided differences on that lower set, which is unisolvent for total degree r), and lifted by
 * CRT to the coefficient bound. Finally F(P(u, v)) = 0 is proved as cb_implicit_vanishes
 * does; failure there (impossible unless the theory is misapplied) is CB_ERR_NUMERIC. Without
 * base points the determinant is returned as it is: for a parameterisation that covers the
 * surface k times (not birational) that is the k-th power of the irreducible equation.
 * Fails with CB_ERR_INVALID if the pencil has rank 0. */
cb_status cb_implicit_from_dixon(cb_implicit_t F, const cb_dixon_pencil_t D,
                                 const cb_dixon_patch_t P, cb_error *err);

/* F from the implicit equation of an analytic surface, exact for its doubles: the local
 * equation (plane z', cylinder x'^2 + y'^2 - r^2, sphere x'^2 + y'^2 + z'^2 - r^2, cone
 * x'^2 + y'^2 - (r + z' tan a)^2 with tan a rounded once, torus (rho^2 + z'^2 + R^2 - r^2)^2 -
 * 4 R^2 rho^2, ellipsoid b^2 c^2 x'^2 + a^2 c^2 y'^2 + a^2 b^2 z'^2 - a^2 b^2 c^2; no
 * normalising division) with x' = X . (p - O), ... substituted in integer arithmetic, every
 * double of the frame and shape taken as the dyadic rational it is. Degree 1, 2 or 4,
 * primitive. So a cylinder of radius 3/8 about a line at a dyadic offset gives integer
 * coefficients with no rounding, and a patch lying on it gives phi = 0 exactly (the
 * normalised equation of cb_analytic_implicit divides by 2 r and would round). */
cb_status cb_implicit_from_analytic(cb_implicit_t F, const cb_analytic_surface *s,
                                    cb_error *err);

/* F = the plane of a planar patch (one whose homogeneous coefficients span a 3-dimensional
 * space, so that cb_dixon_pencil_set refuses it), exactly: the integer vector L with
 * L . P(u, v) = 0 identically, the null space of the 4 x (m+1)(n+1) coefficient matrix
 * (fmpz_mat_nullspace), degree 1, primitive. No rounding: a patch on the plane z = 1 gives
 * exactly z - w, so phi of a curve lying on Q's patch side is exactly divisible by that side.
 * CB_ERR_INVALID when the null space is not one-dimensional. */
cb_status cb_implicit_from_plane_patch(cb_implicit_t F, const cb_dixon_patch_t P, cb_error *err);

/* F = the plane through three homogeneous points h[i] = (w x, w y, w z, w), exactly (the null
 * vector of their 3 x 4 integer matrix), degree 1, primitive. CB_ERR_INVALID when they are
 * collinear. For a patch that is planar up to the rounding of its control points (a planar
 * face turned by a rotation): the plane through three of them. */
cb_status cb_implicit_plane_through(cb_implicit_t F, const double h[3][4], cb_error *err);

/* F at the Euclidean point X (w = 1), from the scaled coefficients: F(X) 2^-exp. Method: sum
 * over monomials with power tables. */
double cb_implicit_eval_d(const cb_implicit_t F, const double X[3]);

/* *vanishes = 1 if F(P(u, v)) is identically zero (exactly, as a polynomial with integer
 * coefficients), else 0. Method: F(P) has bidegree (N m, N n); it is evaluated modulo primes on
 * the (Nm + 1) x (Nn + 1) grid of small integers, where vanishing everywhere means vanishing
 * mod p as a polynomial, until the product of primes exceeds twice the bound
 * ||F||_1 max_q ||P_q||_1^N on its coefficients. The first non-zero value proves
 * non-vanishing. */
void cb_implicit_vanishes(int *vanishes, const cb_implicit_t F, const cb_dixon_patch_t P);

/* F as an fmpz_mpoly in the four variables (x, y, z, w) of ctx (nvars >= 4). */
void cb_implicit_get_mpoly(fmpz_mpoly_t out, const cb_implicit_t F, const fmpz_mpoly_ctx_t ctx);

/* Which of two patches to implicitise (paper footnote 1: the one of lower implicit degree).
 * The degree is bounded by the Dixon rank (the degree of the minor F divides; equal to it
 * without base points), computed by cb_dixon_pencil_rank; the lower rank wins, ties go to the
 * smaller bidegree product and then to P. Returns 0 for P, 1 for Q. Analytic surfaces (degree
 * <= 4) are always the better choice and never reach this function. */
int cb_implicit_choose(const cb_dixon_pencil_t DP, const cb_dixon_pencil_t DQ);

/* ---------------------------------------------------------------- phi = F(Q) --------------- */

typedef struct {
    slong ds, dt;   /* bidegree (N m_Q, N n_Q) */
    fmpz *c;        /* (ds+1)(dt+1) integers, s outer: coefficient of s^i t^j at i (dt+1) + j,
                       in Q's polynomial parameters (local [0,1]^2 for a Bezier patch) */
    slong exp;      /* cd and bern are scaled by 2^-exp */
    double *cd;     /* c 2^-exp */
    double *bern;   /* Bernstein coefficients over Q's box, 2^-exp, same layout */
    double box[4];  /* Q's box */
} cb_phi_struct;
typedef cb_phi_struct cb_phi_t[1];

void cb_phi_init(cb_phi_t phi);
void cb_phi_clear(cb_phi_t phi);

/* phi(s, t) = F(a(s,t), b(s,t), c(s,t), d(s,t)) for the patch Q, exactly. Method: values mod
 * primes on the (ds+1) x (dt+1) grid of small integers, tensor Newton interpolation, CRT up to
 * the bound ||F||_1 max_q ||Q_q||_1^N. The Bernstein form over Q's box [s0, s1] x [t0, t1] is
 * computed exactly too (with s = s0 + (s1 - s0) sigma, the integer transform
 * beta_i = sum_{k<=i} C(M-k, i-k) q_k gives b_i = beta_i / C(M, i), per direction) and rounded
 * once at the end, so bounds read from it are faithful to the exact polynomial. */
cb_status cb_phi_compute(cb_phi_t phi, const cb_implicit_t F, const cb_dixon_patch_t Q,
                         cb_error *err);

/* phi(s, t) 2^-exp by Horner on the scaled power coefficients. */
double cb_phi_eval_d(const cb_phi_t phi, double s, double t);

/* Floating phi without its coefficients: F evaluated at Q(s, t) in doubles, with Q
 * homogeneous (so also where d vanishes): sum c 2^-exp a^i b^j c^k d^l with Q's components
 * scaled as Q->cd. Same zero set as phi; a different positive scale. */
double cb_phi_eval_direct_d(const cb_implicit_t F, const cb_dixon_patch_t Q, double s,
                            double t);

#endif
