/* spline.h — the subdivision route for B-spline/B-spline patch pairs (primer 7;
 * Sederberg and Meyers 1988). Internal to ssi/: the driver (ssi_pairs.c) calls
 * _cb_ssi_spline_pair for Bezier patch pairs whose phi would be of too high a degree for the
 * algebraic route. Not a public API.
 *
 * Certification. A pair of sub-patches is certified when
 *   (a) a direction e is proved to satisfy e . (n_P x n_Q) > 0 for every normal n_P of the
 *       P sub-patch and n_Q of the Q sub-patch: the normals S_u x S_v of a polynomial patch are
 *       convex combinations of the Bernstein coefficients of S_u x S_v (of a rational patch
 *       P / w: positive multiples of N = w (P_u x P_v) - w_u (P x P_v) - w_v (P_u x P), of
 *       bidegree (3m - 1, 3n - 1), since S_u x S_v = N / w^3), so it suffices that
 *       e . (A_i x B_k) > 0 for every pair of coefficients, each decided by an error bound
 *       that excludes zero (coefficients enclosed in interval arithmetic with outward
 *       rounding, de Casteljau subdivision included). Then no two normals are parallel, the
 *       height e . X grows strictly along every intersection branch, no branch closes, and
 *       each branch runs from an entry point to an exit point on the boxes' boundaries;
 *   (b) every intersection of the 4 boundary curves of each sub-patch with the other
 *       sub-patch is found: boxes of (edge parameter, other patch parameters) are excluded by
 *       interval enclosures (natural and mean value form) or hold one simple root proved by
 *       the Krawczyk operator (interval Jacobian, outward rounding); a root whose enclosure
 *       touches the side of its box (a curve through a corner), or two enclosures that
 *       cannot be told apart, make the pair ambiguous;
 *   (c) there are exactly two boundary points (each branch has two ends on the boundary and
 *       no branch closes, so exactly one branch joins them), or none (no intersection). As a
 *       consistency check one must be an entry and one an exit: the sign of the tangent's
 *       parameter velocity across the side (non-zero at a simple root; read in floating
 *       point, |normalised velocity| > 1e-9 required), and the exit must be higher in e . X.
 * Pairs failing (a)-(c) are split (the larger sub-patch, at parameter midpoints, which keeps
 * boxes dyadic) down to a floor; what remains at the floor, or beyond the work budget, is
 * reported uncertified with its parameter boxes. A certified branch is marched in heights
 * h = e . X from entry to exit: at each height the branch is the only point of P = Q in the
 * boxes, so a converged Newton point inside the boxes (1e-12 parameter slack) is on it: no
 * branch jumping. The chord criterion is checked at each chord's midpoint (not a bound).
 *
 * Outside the proof: the Bezier patches themselves are the floating-point result of knot
 * insertion (as for the algebraic route), and the polyline between marched points.
 *
 * Rational patches need positive weights: then every sub-patch lies in the convex hull of its
 * Euclidean control points (homogeneous nets are subdivided, then divided by their weight
 * intervals), and a weight enclosure never reaches 0 over [0,1]^2. */
#ifndef CB_SSI_SPLINE_H
#define CB_SSI_SPLINE_H

#include <math.h>

#include "brep/nurbs.h"
#include "brep/status.h"
#include "ssi/ssi.h"

/* ---------------------------------------------------------------- intervals ---------------- */

/* A closed interval [lo, hi]; operations round outward (one ulp each way), so the exact
 * result of the operation on any members lies inside. */
typedef struct {
    double lo, hi;
} _cb_iv;

/* Outward rounding of a result rounded to nearest: its error is at most |x| 2^-53 or half the
 * smallest subnormal, so these bounds are never tighter than nextafter's. */
static inline double _cb_iv_dn(double x)
{
    return x - (fabs(x) * 0x1p-52 + 0x1p-1074);
}

static inline double _cb_iv_up(double x)
{
    return x + (fabs(x) * 0x1p-52 + 0x1p-1074);
}

static inline _cb_iv _cb_iv_pt(double x)
{
    _cb_iv r = {x, x};
    return r;
}

static inline _cb_iv _cb_iv_add(_cb_iv a, _cb_iv b)
{
    _cb_iv r = {_cb_iv_dn(a.lo + b.lo), _cb_iv_up(a.hi + b.hi)};
    return r;
}

static inline _cb_iv _cb_iv_sub(_cb_iv a, _cb_iv b)
{
    _cb_iv r = {_cb_iv_dn(a.lo - b.hi), _cb_iv_up(a.hi - b.lo)};
    return r;
}

static inline _cb_iv _cb_iv_mul(_cb_iv a, _cb_iv b)
{
    double p0 = a.lo * b.lo, p1 = a.lo * b.hi, p2 = a.hi * b.lo, p3 = a.hi * b.hi;
    double lo = p0 < p1 ? p0 : p1, hi = p0 < p1 ? p1 : p0;
    lo = p2 < lo ? p2 : lo;
    hi = p2 > hi ? p2 : hi;
    lo = p3 < lo ? p3 : lo;
    hi = p3 > hi ? p3 : hi;
    _cb_iv r = {_cb_iv_dn(lo), _cb_iv_up(hi)};
    return r;
}

/* ---------------------------------------------------------------- Bezier patches ----------- */

/* A Bezier patch in its local parameters [0,1]^2, u outer; dom = the caller's parameter box it
 * maps to. Polynomial (rat = 0): control points pts[3 (i (n + 1) + j) + k], exact doubles.
 * Rational (rat = 1): homogeneous control points pts[4 (i (n + 1) + j) + k] = (w x, w y, w z,
 * w), exact doubles, every weight > 0 (so the patch lies in the convex hull of its Euclidean
 * control points, and of those of every sub-patch). dim = 3 + rat values per control point. */
typedef struct {
    int m, n, rat, dim;
    double *pts;
    double dom[4];
} _cb_ssi_bez;

/* From one Bezier patch of cb_nurbs_surface_extract_bezier: polynomial when all weights are
 * equal (then divided out), else rational. CB_ERR_UNSUPPORTED for a weight <= 0 (no convex
 * hull), CB_ERR_INVALID for a patch that is not a single Bezier patch, CB_ERR_NOMEM. */
cb_status _cb_ssi_bez_set(_cb_ssi_bez *b, const cb_nurbs_surface_struct *s, cb_error *err);
void _cb_ssi_bez_clear(_cb_ssi_bez *b);

/* Point and first partials at (u, v) (floating point de Casteljau; rational: quotient rule). */
void _cb_ssi_bez_eval(double X[3], double Xu[3], double Xv[3], const _cb_ssi_bez *b, double u,
                      double v);

/* Enclosures of the point and first partials over the parameter box u x v (interval de
 * Casteljau, outward rounding; a rational patch by X = P / w, X_u = (P_u - X w_u) / w on the
 * homogeneous enclosures). */
void _cb_ssi_bez_eval_iv(_cb_iv X[3], _cb_iv Xu[3], _cb_iv Xv[3], const _cb_ssi_bez *b, _cb_iv u,
                         _cb_iv v);

/* Splits the Bezier curve with d + 1 enclosed control points of dim values (3: Euclidean, 4:
 * homogeneous) c[k stride] at its parameter 1/2 into lo and hi (same layout): enclosures of the
 * halves' control points. */
void _cb_ssi_split_iv(_cb_iv *lo, _cb_iv *hi, const _cb_iv *c, int d, int stride, int dim);

/* The same split at a parameter t in [0, 1] known as an interval (the control points of the
 * pieces over [0, t] and [t, 1] enclosed for every t in it). */
void _cb_ssi_split_iv_at(_cb_iv *lo, _cb_iv *hi, const _cb_iv *c, int d, int stride, int dim,
                         _cb_iv t);

/* In place: the d + 1 enclosed control points c (stride dim) of a curve over [w0, w1] become
 * those of its piece over [a, b] (w0 <= a < b <= w1), the fractions of the box enclosed as
 * intervals so that the result holds for the exact a and b. */
void _cb_ssi_restrict_iv(_cb_iv *c, int d, int dim, double w0, double w1, double a, double b);

/* x / w for an interval w > 0 (outward rounding). */
_cb_iv _cb_iv_div(_cb_iv x, _cb_iv w);

/* Euclidean enclosures (3 per point) of np control points of dim values (4: homogeneous,
 * divided by their weight intervals; 3: copied). */
void _cb_ssi_net_eucl(_cb_iv *out, const _cb_iv *net, int np, int dim);

/* ---------------------------------------------------------------- edge/surface roots ------- */

/* A certified simple root of C(w) = S(a, b): y = (w, a, b) refined by Newton, k its Krawczyk
 * enclosure. */
typedef struct {
    double y[3];
    _cb_iv k[3];
} _cb_ssi_edge_root;

/* All roots of E(w) = S(a, b) with w in [w0, w1] and (a, b) in box = {a0, a1, b0, b1}, where
 * E is the iso-curve of patch C at parameter dir (0: u) fixed to c, w running over the other
 * parameter. cnet (C's degree along w plus 1 points, C->dim values each) and snet (S's net, u
 * outer, S->dim values each) enclose the control points of E over [w0, w1] and of S over box;
 * they give the exclusion tests (convex hulls of the Euclidean points compared along a few
 * axes), subdivided with the boxes. Appends to roots (capacity
 * cap, count *n). Returns 1 when every root was found and certified simple and strictly
 * inside the domain, 0 when ambiguous (a root on or near the domain's boundary, a multiple or
 * near-multiple root, more than cap roots, more than budget boxes, or no memory for the
 * search). The boxes examined are added to *spent. */
int _cb_ssi_edge_roots(_cb_ssi_edge_root *roots, int cap, int *n, const _cb_ssi_bez *C, int dir,
                       double c, double w0, double w1, const _cb_iv *cnet, const _cb_ssi_bez *S,
                       const double box[4], const _cb_iv *snet, int budget, long *spent);

/* ---------------------------------------------------------------- patch pairs -------------- */

typedef struct {
    int max_depth;     /* floor: sub-patches are not split below width 2^-max_depth */
    long max_subpairs; /* work budget per patch pair */
    double tol, chord, max_seg;
    long max_edge_boxes; /* and of the boundary-root searches' boxes; 0: not bounded */
    int band; /* 1: a sub-pair without a direction that is proved within tol of the other
                 (slab_within) is not split further at any size, so that a tangential curve's
                 contact band is covered by sub-pairs of the slab's size, not of STOP_TOL tol
                 (the caller's second pass when the budget ran out); it stops at the first
                 sub-pair left uncertified (the caller keeps it only when none is). Other
                 runs stop once a cluster of their tangent sub-pairs is wider than
                 WT_MAX_TOL tol (only a band run resolves it) */
} _cb_ssi_spline_opts;

typedef struct {
    long subpairs;             /* sub-patch pairs examined */
    long certified;            /* of them certified (with or without a branch) */
    long branches;             /* branches marched */
    long uncertified;          /* sub-patch pairs left at the floor or over the budget */
    double box_p[4], box_q[4]; /* union of their parameter boxes, local [0,1]^2 of P and Q */
    int ambiguous_roots;       /* uncertified ones whose boundary roots were ambiguous */
    int no_direction;          /* uncertified ones without a proved direction e */
    int many_branches;         /* uncertified ones with more than one branch */
    int march_failed;          /* branches whose marching did not converge (reported uncertified) */
    int nomem;                 /* 1: memory ran out, the pair stopped (reported uncertified) */
    long unresolved;           /* sub-pairs left for _cb_ssi_tiny_resolve (see below) */
    long edge_boxes;           /* boxes of the boundary root searches (_cb_ssi_edge_roots) */
    int wide;                  /* 1: the first run stopped at a tangent cluster wider than the
                                  near-node bound (its rest reported over budget) */
    long side_subpairs;        /* certified sub-pairs along a side lying on the other patch's
                                  (_cb_ssi_coside), once per such side, whose rules are
                                  within tolerance */
    long side_pieces;          /* the pieces along such sides among their pieces */
    double side_width;         /* the largest proved gap of those sides */
    double side_box_p[4], side_box_q[4]; /* their parameter boxes, local [0,1]^2 */
    double side_lo[3], side_hi[3];       /* and their 3D box */
} _cb_ssi_spline_stats;

/* A side of P that lies on a side of Q over a common range (a curve along patch sides, as where
 * two faces share an edge): sides 0 u = 0, 1 u = 1, 2 v = 0, 3 v = 1 of the local [0,1]^2; the
 * range [t0, t1] along P's side, paired with Q's side parameters m0, m1 (affinely between);
 * width: proved bound (CB_SSI_COSIDE_WIDTH tol at most, ssi_tol.h) of the distance between the
 * two sides' points paired so, over the range (the Bernstein coefficients of their difference,
 * interval arithmetic); ep, eq: widths of the strips of P and Q along the sides (local
 * parameters) within CB_SSI_COSIDE_STRIP tol of them in 3D (a bound of the partial derivative
 * across). */
typedef struct {
    int sp, sq;
    double t0, t1, m0, m1;
    double width, ep, eq;
} _cb_ssi_coside;

/* The sides of polynomial patches P and Q that lie on each other as above, at most cap of
 * them, into out; their number (0 for rational patches, and where sides only touch or meet at
 * a point, or are reparametrised other than affinely: then the boundary roots along them are
 * searched as usual). Sides are paired by projecting their ends on each other; only the proof
 * of the width decides. */
int _cb_ssi_cosides_find(_cb_ssi_coside *out, int cap, const _cb_ssi_bez *P, const _cb_ssi_bez *Q,
                         double tol);

/* The side parameter of Q paired with parameter t of P's side (the ends exactly), and back. */
double _cb_ssi_coside_mu(const _cb_ssi_coside *r, double t);
double _cb_ssi_coside_tau(const _cb_ssi_coside *r, double mu);

/* A sub-pair the tests could not certify, left at the 3D floor (both sub-patches within tol / 8)
 * or within 8 tol and proved within tol of each other (slab: one slab of width <= tol holds
 * both control nets, each a graph over its plane). Boxes in 3D and in the patches' domains; a
 * candidate point X of both patches in it (P's middle and its foot on Q), with its parameters;
 * job: the caller's index of the patch pair. */
typedef struct {
    double lo[3], hi[3];
    double bp[4], bq[4];
    double X[3], uv[2], st[2];
    double gap; /* distance between the two surface points X is the middle of */
    int reason, slab, job, root;
    int blocker; /* not a tangent region's member but a sub-pair left uncertified (at the
                    parameter floor or over the budget): a region meeting it stays open */
} _cb_ssi_tiny;

/* 1 when the 3D boxes of a and b meet within slack. */
static inline int _cb_ssi_tiny_meet(const _cb_ssi_tiny *a, const _cb_ssi_tiny *b, double slack)
{
    for (int q = 0; q < 3; q++)
        if (a->hi[q] + slack < b->lo[q] || b->hi[q] + slack < a->lo[q])
            return 0;
    return 1;
}

typedef struct {
    slong n, alloc;
    _cb_ssi_tiny *t;
} _cb_ssi_tiny_set;

void _cb_ssi_tiny_set_init(_cb_ssi_tiny_set *ts);
void _cb_ssi_tiny_set_clear(_cb_ssi_tiny_set *ts);

/* The intersection of the Bezier patches P and Q, polynomial or rational (certified as above):
 * one piece per certified branch appended to out, points refined onto both patches
 * (|P - Q| <= tol / 100), uv / st in the patches' domains (P->dom, Q->dom), chords within chord
 * and max_seg. Sub-pairs are split until certified, or until both sub-patches are within tol / 8
 * in 3D, or within 8 tol and proved within tol of each other, which are appended to tiny (with
 * job) for _cb_ssi_tiny_resolve (with the pieces of the sides lying on each other that both
 * sub-patches reach, _cb_ssi_coside, flagged tangential); those at the parameter floor or over
 * the budget are uncertified. Deterministic (serial inside). */
void _cb_ssi_spline_pair(_cb_ssi_piece_set *out, _cb_ssi_spline_stats *stats, const _cb_ssi_bez *P,
                         const _cb_ssi_bez *Q, const _cb_ssi_spline_opts *o,
                         _cb_ssi_tiny_set *tiny, int job);

/* A tangent region resolved within the tolerance by _cb_ssi_tiny_resolve: its 3D box and
 * diameter, the point (of both surfaces, parameters in the domains, P's uv and Q's st) its piece
 * ends moved onto, how many did, whether no branch ends in it or passes it (lone: an isolated
 * contact point, unless within WT_MAX_TOL tol of a region branches end in or of a wider lone
 * one), whether every member was proved within tol of the other surface (slab), and the pair
 * of its first member. A contact band's node (_cb_ssi_band_node) has one record, and each pair
 * of ends it joins along a trace one more (ends 2, the band's box). */
typedef struct {
    double lo[3], hi[3], width;
    double X[3], uv[2], st[2];
    int ends, slab, lone;
    slong job;
} _cb_ssi_tiny_region;

/* Within the tolerance (tolerance-certificates.md sections 2 and 5), for the unresolved sub-pairs
 * of all patch pairs of two surfaces (tiny[k]: those of pair k, pieces sets[k]): they are
 * clustered (3D boxes meeting within tol / 10), and a cluster that meets no sub-pair left
 * uncertified (blocker) and has a 3D diameter at most tol, or at most 1000 tol with every member
 * proved within tol, is resolved: the piece ends (of every pair) in its box grown by tol move onto
 * one point of both surfaces in it (a member's candidate whose surface points are within tol,
 * moved onto the intersection by _cb_ssi_band_zero_point within the cluster's diameter of its box
 * where that converges; with no candidate the cluster is not resolved), pieces lying wholly in it
 * are dropped, and with no end it gives one isolated contact point (appended to the set of its
 * first member's pair; not where it lies within WT_MAX_TOL tol of a region branch ends joined, or
 * of a wider region giving such a point); two pieces of sides lying on the other surface from its
 * point to one patch corner (the node where those sides cross, just outside its box, within its
 * diameter) are dropped as well. A larger cluster is not resolved unless it is a contact band
 * (below): bad[k] is set for each pair k with a member in it, unres[k] counts them, and
 * bad_box[8k .. 8k + 8) is the union of their parameter boxes (P's then Q's {u0, u1, v0, v1}, in
 * the domains; set where bad[k] is). Per
 * resolved region: *regions, *nodes (of them with branch ends), *width (largest diameter), and a
 * record in *out (*nout of them, malloc'd, the caller frees; NULL when none) whose index the moved
 * piece ends (and the contact point) carry in _cb_ssi_end.region, so stitching joins them;
 * within[k] is set for every pair k with a member in a resolved region or a piece end moved. A
 * cluster wider than 1000 tol with every member proved within tol, that meets no sub-pair left
 * uncertified and holds no piece end (in a member's box grown by tol; the pieces of a side lying
 * on the other surface, which run on through the members reaching it, not counted), is a contact
 * band: its curves are the valley of the distance (_cb_ssi_band_trace on P and Q, the whole
 * surfaces whose domains the pieces' parameters are in; NULL: not tried), appended to the set of
 * its first member's pair, the region recorded (no node, ends 0). Such a cluster that holds a
 * piece end, or where no valley was traced, is one node (_cb_ssi_band_node: the ends joined to it
 * along the zero set of the distance; with no end, one isolated contact point), recorded as the
 * small regions are. -1 when out of memory. */
int _cb_ssi_tiny_resolve(_cb_ssi_piece_set *sets, slong nsets, const _cb_ssi_tiny_set *tiny,
                         char *bad, long *unres, double *bad_box, double tol, long *regions,
                         long *nodes, double *width, _cb_ssi_tiny_region **out, slong *nout,
                         char *within, const cb_ssi_surface *P, const cb_ssi_surface *Q,
                         double chord, double max_seg);

/* The curves of a contact band (ssi_band.c): the m[0 .. nm) members of one cluster of sub-pairs
 * proved within tol of each other (slab_within), P and Q the whole B-spline surfaces (uv, st of
 * the members in their domains), sets[0 .. nsets) the pieces of all patch pairs (for the sides of
 * P lying on sides of Q: their pieces, `side`). The rule (tolerance-certificates.md section 2,
 * "the curve reported inside it is the minimum of the distance"): with D(u, v) the signed distance
 * of P(u, v) from its foot on Q along Q's normal, the curve is the valley of D, the points where
 * D's derivative across the valley (along the eigenvector of D's Hessian of largest eigenvalue) is
 * 0, traced from a member's point by steps along the valley, each point settled onto it by
 * Newton's method across it, the chords within chord (sagitta, by the settled midpoint) and
 * max_seg; a curve ends where it closes, on a side of P's domain (that parameter held, its `fixed`
 * bit set; on a side lying on Q, where D vanishes along the side, where it meets it), or where Q's
 * domain ends. Members that a side's piece crosses (their box grown by 2 chord + 10 tol) have that
 * side for their curve: they seed none. Checked, or 0 (not resolved): every point within tol of
 * both surfaces (|D| <= tol) and in a member's box grown by tol (in the region proved within tol),
 * every member's valley point within 2 chord + 10 tol of a traced curve or on a side lying on Q (a
 * member off every curve seeds another; at most 16); where P has sides lying on Q, a member
 * without a valley point (Newton's method not converging, or no valley followed from it: beside
 * the node where the valley meets such a side, where it is not defined) crossed by a curve or a
 * side's piece, or its box meeting (within tol) that of a member so crossed: the region left to
 * the curves there is one member wide; elsewhere (as around an isolated contact, a bowl of D whose
 * valley is any line through its bottom) such a member leaves the band unresolved. Not proved:
 * that the valley is unique between the points, or that the surfaces touch there (a near miss
 * within tol reads as a tangential curve). On success the curves are appended to out as tangential
 * pieces flagged within (stitching marks their curves not certified); 1, 0 not resolved (out may
 * hold part of the curves: the caller drops them), -1 out of memory. Only B-spline P and Q (0
 * otherwise). */
int _cb_ssi_band_trace(_cb_ssi_piece_set *out, const _cb_ssi_piece_set *sets, slong nsets,
                       const cb_ssi_surface *P, const cb_ssi_surface *Q,
                       const _cb_ssi_tiny *const *m, slong nm, double tol, double chord,
                       double max_seg);

/* A contact band that is no valley curve (ssi_band.c): the m[0 .. nm) members of one cluster wider
 * than WT_MAX_TOL tol, each proved within tol of the other surface (slab_within), that holds
 * branch ends (a near-tangent node, cusp or touching point seen coarsely) or where
 * _cb_ssi_band_trace traced no curve (an isolated contact whose distance is a bowl). The rule
 * (tolerance-certificates.md section 2: the surfaces lie within tol of each other all over the
 * band, so any point and path in it is an intersection within tol): the band is one node that
 * every end of a piece of sets lying in a member's box grown by tol joins (not those of a side
 * lying on the other surface, which runs on through the band, and which is not dropped below
 * either). From each end the zero set of D (the signed distance of _cb_ssi_band_trace) is traced
 * into the band (steps along its level line of at most 2 chord, each point moved onto D = 0 by
 * Newton's method until it stops moving, kept when that moved it at most a quarter of the step,
 * the step's middle is within chord of its chord and D's gradient keeps its side: the other of two
 * curves of the zero set that come close, as at a touching point or node, has it the other way)
 * until it leaves the members' box, comes within 2 chord + 10 tol of another end, or cannot go on.
 * A piece with both ends in the band (a sub-pair's piece between two members) is not traced; one
 * whose every point lies within 2 chord + 10 tol of a trace is dropped (the trace follows its
 * curve). Two ends one's trace came to are one curve through the band (a gap its members left in
 * it): joined along that trace at the other end's point, a record of their own (unless the other's
 * trace came to a third end). The node, for the ends not so linked: the first point of one trace
 * within 2 chord + 10 tol of another trace that its start is not on (where two curves of the zero
 * set meet), the one where D's gradient is least; with no such point, the trace point where it is
 * least; with no trace, a member's candidate whose surface points are within tol, the one nearest
 * the ends' mean (with no end, the centre of the band's box). Each end's spoke to the node: its
 * trace as far as its point nearest the node, then the straight line in P's parameters (feet on
 * Q), chords halved to chord and max_seg, or where a point of it is not within tol of Q the line
 * through the points of the members on the way (boxes meeting within tol / 10). Pieces lying
 * wholly in the members' boxes are dropped. Checked, or 0 (not resolved, sets unchanged): every
 * spoke point within tol of its foot on Q and in the members' box grown by tol. On success the
 * records are appended to *out (*nout held, *alloc allocated; _cb_ssi_region_slot): the node's
 * first (box and diameter the band's, job that of its first member, the node's point, ends the
 * number joined to it, lone: no end and no piece passing through a member's box, one isolated
 * contact point, which the caller adds), then one per link (ends 2); the moved ends carry their
 * record's index in end.region (within[k] set for their set k). Not proved: which ends the true
 * curves join inside the band (the band is one node within tol), or that the surfaces touch there.
 * 1, 0, -1 out of memory. Only B-spline P and Q (0 otherwise). */
int _cb_ssi_band_node(_cb_ssi_piece_set *sets, slong nsets, const cb_ssi_surface *P,
                      const cb_ssi_surface *Q, const _cb_ssi_tiny *const *m, slong nm,
                      double tol, double chord, double max_seg, slong job,
                      _cb_ssi_tiny_region **out, slong *nout, slong *alloc, char *within);

/* Room for the record *out + n of _cb_ssi_tiny_resolve's records (n held, alloc allocated;
 * grown by doubling): it, or NULL when out of memory (*out as it was). */
_cb_ssi_tiny_region *_cb_ssi_region_slot(_cb_ssi_tiny_region **out, slong n, slong *alloc);

/* The point of P at uv (foot st on Q, X their middle) moved onto the intersection by Newton's
 * method on the signed distance (ssi_band.c, as the zero set's traces of _cb_ssi_band_node),
 * kept when it converges with the middle inside the box lo, hi grown by slack + tol and both
 * surface points within tol: 1 (uv, st, X updated), 0 (unchanged; also when P or Q is not
 * B-spline). */
int _cb_ssi_band_zero_point(const cb_ssi_surface *P, const cb_ssi_surface *Q, double uv[2],
                            double st[2], double X[3], const double lo[3], const double hi[3],
                            double slack, double tol);

/* ---------------------------------------------------------------- coincidence ------------- */

/* Pre-filter (ssi_coincide.c; never decides): every point of a CB_SSI_COINCIDENT_GRID square
 * grid of Q within CB_SSI_COINCIDENT_FILTER tol of P's map continued over local [-1, 2]^2
 * (projection), the centre first. */
int _cb_ssi_coincide_filter_bez(const _cb_ssi_bez *P, const _cb_ssi_bez *Q, double tol);

/* Whether the Bezier patch q lies on the continuation of the Bezier patch p (p, q: patches of
 * cb_nurbs_surface_extract_bezier with positive weights; P, Q: the same as _cb_ssi_bez, for the
 * projections): 1 exactly (q(s, t) = p(A(s, t)) for an axis-aligned affine A, possibly
 * swapping the parameters; *width = 0), 2 within tol (every point q(s, t) within *width <=
 * CB_SSI_COINCIDENT_WIDTH tol of the point p(A(s, t)) of p's map), 0 no proof. Candidates for
 * A: the one identifying the patches' domains (the same parameterisation), and the one through
 * p's parameters of q's corners (projection onto p continued), snapped to the 2^-30 grid and
 * as found. Each is checked in exact rational arithmetic (FLINT fmpq, the control data taken as
 * the dyadic rationals they are): p's homogeneous net reparameterised by A (blossoms), the
 * difference D = p(A) w_q - q w_p(A) as a Bernstein polynomial, and max |D_ij|^2 compared with
 * (tol min w_p(A) min w_q)^2 over the weights' Bernstein coefficients (which must be
 * positive): |p(A) - q| = |D| / (w_p(A) w_q) <= max |D_ij| / (min w min w). */
int _cb_ssi_coincide_reparam(double *width, const cb_nurbs_surface_struct *p,
                             const cb_nurbs_surface_struct *q, const _cb_ssi_bez *P,
                             const _cb_ssi_bez *Q, double tol);

#endif
