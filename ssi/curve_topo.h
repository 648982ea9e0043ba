/* curve_topo.h — certified topology of a real plane algebraic curve phi(s, t) = 0 in a rational box
 * (Yang, Jia, Yan, ACM TOG 2023, section 4.3, section 5.5, appendix A; ssi-primer section 6).
 *
 * Input: phi in Z[s, t], given as an fmpz_mpoly in a context with two variables, variable 0
 * being s and variable 1 being t, and a box [s0, s1] x [t0, t1] with rational corners.
 * Output (cb_ctopo_t): a graph whose vertices are points of the curve inside the box (helping
 * points, regular and critical points on critical lines, boundary points, isolated points) and
 * whose edges are pieces of the curve that are monotone in s (or vertical segments s = alpha),
 * with summary counts. The graph is isotopic to the curve inside the box; every connection in
 * it is proved by exact arithmetic or by interval (Arb) arithmetic, never guessed. The method,
 * what it guarantees and what it does not are described in ssi/README.md.
 *
 * Also exported, for the topology driver's own files and for tests: a dense bivariate integer
 * polynomial (cb_bipoly), exact sign and zero tests at real algebraic numbers, principal
 * subresultant coefficients, and the certified analysis of one critical line. */
#ifndef CB_SSI_CURVE_TOPO_H
#define CB_SSI_CURVE_TOPO_H

#include <arb.h>
#include <flint/fmpq.h>
#include <flint/fmpz_mpoly.h>
#include <flint/fmpz_poly.h>
#include <flint/fmpz_poly_mat.h>

#include "brep/status.h"
#include "ssi/roots.h"

/* --------------------------------------------------------------- dense bivariate polynomials */

/* sum_{j < len} c[j](s) t^j with c[j] in Z[s]; len = 0 for the zero polynomial, otherwise
 * c[len - 1] != 0. */
typedef struct {
    slong len, alloc;
    fmpz_poly_struct *c;
} cb_bipoly_struct;
typedef cb_bipoly_struct cb_bipoly_t[1];

/* The functions take cb_bipoly_struct pointers rather than cb_bipoly_t array parameters: GCC 12
 * checks array parameters against a size it misjudges for members of structs reached through
 * pointers (-Wstringop-overread false positives). */

void cb_bipoly_init(cb_bipoly_struct *p);
void cb_bipoly_clear(cb_bipoly_struct *p);
void cb_bipoly_set(cb_bipoly_struct *p, const cb_bipoly_struct *q);
void cb_bipoly_swap(cb_bipoly_struct *p, cb_bipoly_struct *q);
slong cb_bipoly_deg_s(const cb_bipoly_struct *p); /* -1 for zero */

/* From / to an fmpz_mpoly in two variables (0 = s, 1 = t). */
void cb_bipoly_set_fmpz_mpoly(cb_bipoly_struct *p, const fmpz_mpoly_t f,
                              const fmpz_mpoly_ctx_t ctx);
void cb_bipoly_get_fmpz_mpoly(fmpz_mpoly_t f, const cb_bipoly_struct *p,
                              const fmpz_mpoly_ctx_t ctx);

/* d = dp/dt and d = dp/ds; d may alias p. */
void cb_bipoly_derivative_t(cb_bipoly_struct *d, const cb_bipoly_struct *p);
void cb_bipoly_derivative_s(cb_bipoly_struct *d, const cb_bipoly_struct *p);

/* out(t) = den * p(s, t) for the smallest positive integer den making it integral: the fibre
 * over a rational s, with the same roots and signs as p(s, .). */
void cb_bipoly_eval_s_fmpq(fmpz_poly_t out, const cb_bipoly_struct *p, const fmpq_t s);

/* out(s) = den * p(s, t), den > 0 as above: the restriction to a horizontal line. */
void cb_bipoly_eval_t_fmpq(fmpz_poly_t out, const cb_bipoly_struct *p, const fmpq_t t);

/* y contains p(s, t) for every s in the ball s and every t in the ball t (Horner in s, then t,
 * in ball arithmetic at precision prec). */
void cb_bipoly_eval_arb(arb_t y, const cb_bipoly_struct *p, const arb_t s, const arb_t t,
                        slong prec);

/* r(s) = Res_t(f, g), the determinant of the Sylvester matrix with the formal degrees
 * f->len - 1 and g->len - 1 (0 if f or g is zero; c^n for f = c constant in t and g of degree
 * n, likewise for g; 1 for two constants). Exact, by evaluation at s = 0, 1, ... modulo
 * primes above 2^59 (points where a leading coefficient in t vanishes skipped), interpolation
 * and Chinese remaindering, over as many primes as a proved coefficient bound requires
 * (ssi/README.md). CB_ERR_INVALID if f or g is not normalised (zero leading coefficient). */
cb_status cb_bipoly_resultant(fmpz_poly_t r, const cb_bipoly_struct *f, const cb_bipoly_struct *g,
                              cb_error *err);

/* r = Res_t(p, p_t) for a normalised p (cb_bipoly_resultant, which cannot fail then). */
void cb_bipoly_resultant_dt(fmpz_poly_t r, const cb_bipoly_struct *p);

/* d = det A for a square matrix over Z[s] (1 for 0 x 0), exactly, by the same scheme as
 * cb_bipoly_resultant (nmod_mat_det at each point). CB_ERR_INVALID if A is not square. */
cb_status cb_fmpz_poly_mat_det(fmpz_poly_t d, const fmpz_poly_mat_t A, cb_error *err);

/* d = det of the size x size (size >= 1) matrix whose entry (i, j) is poly[idx[i size + j]],
 * zero where that index is -1; each distinct polynomial is evaluated once per point. */
void _cb_fmpz_poly_mat_det_indexed(fmpz_poly_t d, const fmpz_poly_struct *poly, slong npoly,
                                   const slong *idx, slong size);

/* ------------------------------------------------------------ real algebraic numbers ------ */

/* A real algebraic number alpha given by a squarefree r in Z[s] and an isolating interval:
 * lo == hi means alpha = lo; otherwise alpha is the only root of r in the open (lo, hi), and
 * r(lo), r(hi) != 0. */

/* 1 if p(alpha) = 0, else 0. Exact: the roots of gcd(p, r) are roots of r, so alpha is one of
 * them iff gcd(p, r) changes sign on the isolating interval. */
int cb_ctopo_alg_vanishes(const fmpz_poly_t p, const fmpz_poly_t r, const fmpq_t lo,
                         const fmpq_t hi);

/* Principal subresultant coefficient psc_j(s) of f = h and g = dh/dt in t, with the formal
 * degrees n = h->len - 1 and n - 1 (Sylvester 1840; Basu, Pollack, Roy, Algorithms in Real
 * Algebraic Geometry, section 4.2): the determinant of the (2n - 1 - 2j)-square matrix of the
 * coefficients of t^(n-2-j) f, ..., f, t^(n-1-j) g, ..., g on t^(2n-2-j), ..., t^j. With
 * col < j, the column of t^j is replaced by that of t^col, giving the coefficient sres_{j,col}
 * of t^col in the j-th subresultant. psc_0 is the resultant. At a real alpha where the leading
 * coefficient of h does not vanish, deg gcd(h(alpha, t), h_t(alpha, t)) is the least j with
 * psc_j(alpha) != 0, and that gcd is proportional to sum_i sres_{j,i}(alpha) t^i.
 * Symbolic version (cb_fmpz_poly_mat_det) and ball version at an s-ball (arb_mat_det). */
void cb_ctopo_sres_coeff(fmpz_poly_t out, const cb_bipoly_struct *h, slong j, slong col);
void cb_ctopo_sres_coeff_arb(arb_t out, const cb_bipoly_struct *h, slong j, slong col,
                             const arb_t s, slong prec);

/* --------------------------------------------------------------------------- topology ------ */

#define CB_CTOPO_SIDE_S0 1u
#define CB_CTOPO_SIDE_S1 2u
#define CB_CTOPO_SIDE_T0 4u
#define CB_CTOPO_SIDE_T1 8u

typedef enum {
    CB_CTOPO_HELPING = 0, /* on a helping line (paper eq. 18): a regular point of a branch */
    CB_CTOPO_FIBRE,       /* regular point (h_t != 0) on a critical line, inside the box */
    CB_CTOPO_BOUNDARY,    /* regular point on a side of the box */
    CB_CTOPO_CRITICAL,    /* h = h_t = 0 with branches through it (fold, node, cusp, ...) */
    CB_CTOPO_ISOLATED     /* a curve point no branch arrives at or leaves from */
} cb_ctopo_kind;

/* A point of the curve. Coordinates: s in [s_lo, s_hi], t in [t_lo, t_hi] (equal ends: exact),
 * with double approximations s, t inside them. */
typedef struct {
    cb_ctopo_kind kind;
    unsigned sides;  /* CB_CTOPO_SIDE_* bits of the box sides the point lies on */
    int singular;    /* h_s = h_t = 0 for the squarefree part h of phi */
    int tangential;  /* lies on a repeated factor of phi (see cb_ctopo_struct) */
    slong line;      /* index of its critical line in line[], -1 for helping points */
    slong degree;    /* number of edge ends at it */
    slong component; /* index of its connected component */
    slong rank, count; /* helping points: index from below among the roots on its helping
                          line, and their number (exact, however close the roots are) */
    fmpq_t s_lo, s_hi, t_lo, t_hi;
    double s, t;
} cb_ctopo_vertex_struct;

/* A piece of the curve between two vertices, v0 with the smaller s. Branch edges are graphs
 * t = y(s) over (s(v0), s(v1)) containing no other vertex; vertical edges lie on a line
 * s = alpha with phi(alpha, t) = 0 identically, between consecutive vertices on it. */
typedef struct {
    slong v0, v1;
    int vertical;
    int tangential; /* lies on a repeated factor of phi */
} cb_ctopo_edge_struct;

/* A critical line s = alpha: a real root of D(s) = Res_t(h, h_t) lc_t(h) h(s, t0) h(s, t1)
 * cont(s) in [s0, s1] (cont the content of phi in t), or the side s0 or s1 of the box. The
 * helping lines left < alpha < right bound an interval holding no other critical value. */
typedef struct {
    fmpq_t lo, hi;         /* isolating interval of alpha; lo == hi when alpha is rational */
    fmpq_t left, right;    /* helping lines; equal to alpha on the sides s0 and s1 */
    int has_left, has_right;
    int vertical;          /* phi(alpha, t) vanishes identically: a vertical segment */
    int vertical_tangential;
    slong gcd_deg;         /* deg gcd(h(alpha, t), h_t(alpha, t)) */
    double s;
} cb_ctopo_line_struct;

typedef struct {
    slong n_lines;
    cb_ctopo_line_struct *line;
    slong n_vertices, alloc_vertices;
    cb_ctopo_vertex_struct *vertex;
    slong n_edges, alloc_edges;
    cb_ctopo_edge_struct *edge;

    slong n_components; /* connected components of the curve in the box */
    slong n_loops;      /* components that are closed curves touching no side of the box */
    slong n_isolated;   /* isolated points (components that are a single point) */
    slong n_singular;   /* singular points of the squarefree part (nodes, cusps, isolated,
                           crossings with vertical lines) */
    int *component_tangential; /* per component: every edge (or its single point) lies on a
                                  repeated factor of phi */
    unsigned sides_on_curve;   /* CB_CTOPO_SIDE_* bits of box sides contained in the curve */
    int has_repeated_factor;   /* phi is not squarefree */
    cb_bipoly_t h; /* the primitive squarefree part of phi without its content in t, whose
                      zeros the graph describes (what a tracer follows; len 0 until computed) */
} cb_ctopo_struct;
typedef cb_ctopo_struct cb_ctopo_t[1];

void cb_ctopo_init(cb_ctopo_t T);
void cb_ctopo_clear(cb_ctopo_t T);

/* Tolerances and limits (all explicit). */
typedef struct {
    slong coord_bits;   /* output coordinate intervals refined to width <= 2^-coord_bits
                           where exact refinement is cheap (s of every vertex, t of helping
                           points); fibre points keep their certified boxes */
    slong prec;         /* initial Arb working precision, bits */
    slong max_attempts; /* refinements of one critical line before giving up (CB_ERR_NUMERIC) */
    slong max_depth;    /* bisection depth of the fibre partition per attempt; default 64 */
} cb_ctopo_opts;

void cb_ctopo_opts_default(cb_ctopo_opts *o);

/* Topology of {phi = 0} in [s0, s1] x [t0, t1] (s0 < s1, t0 < t1, phi != 0).
 * Method (details in ssi/README.md): squarefree decomposition of phi; content in t gives the
 * vertical lines; critical lines are the roots of D (above) isolated exactly (cb_roots) plus
 * s0 and s1; between helping lines the branches are ordered graphs matched by rank; at each
 * critical line the t-range is cut into boxes certified in ball arithmetic (no curve crossing
 * a box's horizontal edges, and a t-derivative of order m not vanishing in it, so at most m
 * roots per vertical line) around the fibre roots, whose multiplicities are exact (rational
 * alpha: squarefree factorisation of phi(alpha, t); irrational alpha: principal subresultant
 * coefficients, with a single multiple root certified). Every branch entering a box ends at
 * its fibre point.
 * Errors: CB_ERR_INVALID (bad box, zero phi, not two variables); CB_ERR_UNSUPPORTED when an
 * irrational critical fibre holds more than one multiple root ("critical fibre not in generic
 * position") or the leading coefficient in t vanishes at an irrational critical value;
 * CB_ERR_NUMERIC when a fibre could not be certified within opts->max_attempts. On error T
 * is left empty. */
cb_status cb_ctopo_compute(cb_ctopo_t T, const fmpz_mpoly_t phi, const fmpz_mpoly_ctx_t ctx,
                          const fmpq_t s0, const fmpq_t s1, const fmpq_t t0, const fmpq_t t1,
                          const cb_ctopo_opts *opts, cb_error *err);

/* -------------------------------------------------- one critical line (used by topo.c) ----- */

/* The squarefree curve data the line analysis needs. */
typedef struct {
    cb_bipoly_t h;       /* primitive squarefree part of phi without its content in t */
    cb_bipoly_t rep;     /* product of the repeated factors of phi (len 0 if none) */
    fmpz_poly_t rep_res; /* Res_t(rep, rep_t), when rep has positive degree in t */
    fmpz_poly_t res;     /* Res_t(h, h_t) */
    fmpz_poly_t lc;      /* leading coefficient of h in t */
    fmpz_poly_t bnd[2];  /* h(s, t0), h(s, t1), each divided by the power of (t - t_i) in h */
    int side_t[2];       /* t - t0 (resp. t - t1) divides h */
    fmpq_t s0, s1, t0, t1;
    const cb_ctopo_opts *opts;
    slong prec; /* working precision of ball tests: opts->prec plus the bits that cancel among
                   the terms of h on the box (coefficient size, degrees, box magnitude) */
} cb_ctopo_curve_struct;

/* A certified box [line->left, line->right] x [c, d] of a critical line. It holds at most one
 * fibre root (a root of h(alpha, t) with alpha the critical value), no curve point crosses its
 * horizontal edges t = c, t = d inside the box (t0 and t1 excepted, where nothing crosses
 * anyway), and every branch entering it through its vertical sides ends at that root. */
typedef struct {
    fmpq_t c, d;
    fmpq_t t_lo, t_hi;   /* enclosure of the fibre root (t_lo == t_hi: exact) */
    slong mult;          /* multiplicity of the root in h(alpha, t); 1 for unpinned boxes */
    int has_root;        /* the box holds a fibre root */
    unsigned sides;      /* CB_CTOPO_SIDE_T0 / T1 when the root is exactly t0 / t1 */
    int singular;        /* h_s = h_t = 0 at the root */
    int tangential;      /* the root lies on a repeated factor (decided for mult > 1 and for
                            boundary roots) */
    slong n_left, n_right;         /* helping roots of the box on each side */
    slong first_left, first_right; /* index of the first of them */
} cb_ctopo_fibre_box_struct;

/* The analysis of one critical line s = alpha: its boxes, sorted by t and disjoint, and the
 * roots of h(left, t) and h(right, t) in [t0, t1] (every one of them inside exactly one box). */
typedef struct {
    slong n_box, alloc_box;
    cb_ctopo_fibre_box_struct *box;
    cb_roots_t left_roots, right_roots;
} cb_ctopo_fibre_struct;
typedef cb_ctopo_fibre_struct cb_ctopo_fibre_t[1];

void cb_ctopo_fibre_init(cb_ctopo_fibre_t F);
void cb_ctopo_fibre_clear(cb_ctopo_fibre_t F);

/* Analyses the line L (its lo, hi, left, right, has_left, has_right set by the caller; the
 * helping lines hold no critical value but alpha between them). alpha is root k of cv (the
 * roots of C->disc in [s0, s1]) when lo < hi; a rational alpha (lo == hi) needs no k.
 * Method: the fibre roots of multiplicity > 1 are pinned exactly (rational alpha: squarefree
 * factorisation of h(alpha, t); irrational alpha: gcd degree k from subresultants, the single
 * multiple root beta = -sres_{k,k-1}(alpha) / (k psc_k(alpha)) of multiplicity k + 1, proved
 * single by the identity gcd = psc_k (t - beta)^k) and boxed with the t-derivative of their
 * order non-zero on the box; the rest of [t0, t1] is bisected into boxes where h or h_t is
 * non-zero (ball arithmetic over the whole s-range [left, right]); when a check fails the
 * s-range shrinks (alpha's interval is refined, or the gap eps of a rational alpha divided by
 * 16) and the boxes are rebuilt, up to opts->max_attempts times.
 * Sets L->gcd_deg. Errors: CB_ERR_UNSUPPORTED (see cb_ctopo_compute), CB_ERR_NUMERIC. */
cb_status cb_ctopo_fibre_analyse(cb_ctopo_fibre_t F, const cb_ctopo_curve_struct *C,
                                cb_roots_t cv, slong k, cb_ctopo_line_struct *L, cb_error *err);

#endif
