/* ssi.h — intersection curves of two surfaces: the driver of the topology-guaranteed SSI
 * (Yang, Jia, Yan, ACM TOG 2023, sections 4.1, 4.4, 5.3, 5.4, appendix B; ssi-primer 7-8).
 *
 * Pipeline for two surfaces A and B (ssi_pairs.c):
 *   1. Bezier extraction of the spline side(s); OBB culling of patch pairs (section 4.1).
 *   2. One side, P, is implicitised: an analytic surface by its exact equation (section 5.3);
 *      of two splines a planar one (its plane), else the one of lower patch bidegree, per
 *      Bezier patch (Dixon, ssi/implicit.h).
 *      The other side, Q, is parameterised: phi(s, t) = F(Q(s, t)) per patch pair.
 *   3. A patch pair whose Bernstein coefficients of phi have one strict sign has no
 *      intersection (proved). Otherwise cb_ctopo_compute gives the certified topology graph of
 *      phi = 0 in Q's patch box.
 *   4. Tracing (trace.c): every monotone branch between its vertices, in the order the graph
 *      certifies; chains through degree-2 vertices.
 *   5. Lifting, refinement onto both surfaces and clipping to P's parameter box (clip.c,
 *      section 4.4): split where P's parameters leave the box, keep pieces whose representative
 *      point inverts inside (Dixon inversion for spline patches, the own parameters for
 *      analytic surfaces).
 *   6. Stitching (ssi_stitch.c): pieces of all patch pairs joined across patch boundaries into
 *      maximal curves by the identity of their ends (the graphs' vertices, exact boundary roots
 *      on shared sides, enclosures), never by distance alone; duplicates on shared boundaries
 *      removed; in patch-pair index order, so the output does not depend on the number of
 *      threads.
 * Every result has one of three outcomes (cb_ssi_outcome; ssi/ssi_tol.h names every rule):
 * certified, resolved within tolerance (a region listed in r->region), or refused (listed in
 * r->failed: a patch pair the topology stage cannot certify (CB_ERR_UNSUPPORTED or
 * CB_ERR_NUMERIC) and, for two B-spline patches, the subdivision route then cannot either, or
 * an ambiguous join wider than tol), never dropped silently. The result container's
 * operations are in ssi_result.c.
 *
 * Spline/spline patch pairs whose phi would exceed opts.max_phi_degree (bicubic x bicubic: 54)
 * take the subdivision route instead (ssi/spline.h, spline_*.c; primer 7): sub-patch pairs are
 * split until a direction e with e . (n_P x n_Q) > 0 is proved over both normal cones, and
 * the single branch such a pair holds (if any) is fixed by certified boundary/surface roots and
 * marched in the height e . X. Sub-pairs left at the floor (tangency, near-tangency, singular
 * points, surfaces closer than round-off without meeting) are listed in r->failed with their
 * parameter boxes; the certified branches of the same patch pair are still output. Rational
 * patches take it too (normal cones from w (P_u x P_v) - w_u (P x P_v) - w_v (P_u x P), hulls of
 * the Euclidean control points, positive weights). A rational P patch of degree <= 2 is
 * implicitised first and keeps the algebraic route when its implicit degree fell below 2 m n
 * (exact conic weights such as 1, 1, 2 have base points: a cylinder or sphere piece gives 2);
 * with rounded weights (sqrt(2)/2) it takes the subdivision route.
 *
 * Analytic/analytic pairs (ssi_analytic.c): closed forms for the special positions (planes,
 * parallel or coaxial or tangent cylinders, coaxial surfaces of revolution incl. every
 * plane/sphere and sphere/sphere pair, planes through a cone's apex or a torus' axis,
 * touching points), decided within tol (distances) and tol / size (directions); the rest by
 * the general route: one surface as its exact rational B-spline against the other's implicit
 * equation (the analytic/NURBS pipeline, certified topology), parameters mapped back to the
 * analytic surface.
 *
 * B-spline faces proved to lie within a thousandth of the tolerance of a plane, cylinder, sphere
 * or cone (any net, knots and parameterisation: a candidate fitted to samples, then a Bernstein
 * bound of its equation over every Bezier patch; ssi_recog.c) take those closed forms when one
 * decides the pair, the curves clipped to the B-splines' domains and their parameters found by
 * point inversion (opts.recognise): the rounded conic weights otherwise leave nodes and
 * tangencies (the Steinmetz bicylinder, a plug in its hole) uncertified.
 *
 * Surfaces that coincide give no curves but a cb_ssi_coincident record with the orientation
 * of their normals: exactly (phi = 0, or Q = P reparameterised) or, proved by a rigorous bound,
 * within tol (ssi_coincide.c); samples only choose which pairs try a proof.
 *
 * Faces of revolution and extrusion (cb_ssi_bodies, ssi_body.c) are intersected as the exact
 * rational B-splines of their surfaces over the face's parameter box (cb_topo_surface_to_nurbs:
 * the profile as an exact B-spline, lines, conics as rational quadratics, B-splines as they
 * are, turned or swept), and the curves' parameters on them mapped back to the face's own
 * (angle, profile parameter) by closed forms, strictly increasing in each direction
 * (cb_topo_surface_nurbs_param).
 *
 * Curves are clipped to the faces' parameter boxes; cb_bool_ssi_trim (boolean/bool.h) clips
 * them to the faces' trimming loops. */
#ifndef CB_SSI_SSI_H
#define CB_SSI_SSI_H

#include "brep/analytic.h"
#include "brep/bbox.h"
#include "brep/context.h"
#include "brep/nurbs.h"
#include "brep/topo.h"
#include "ssi/curve_topo.h"
#include "ssi/dixon.h"
#include "ssi/implicit.h"

/* pi to double precision (C11 has no M_PI). */
#define CB_SSI_PI 3.14159265358979323846

/* ---------------------------------------------------------------- input surfaces ----------- */

typedef enum { CB_SSI_ANALYTIC, CB_SSI_NURBS } cb_ssi_surface_kind;

/* A surface to intersect. The NURBS surface is borrowed (it must outlive the call). The
 * analytic surface is restricted to range = {u0, u1, v0, v1}, +-HUGE_VAL for an unbounded
 * direction; an angular direction (u of all but the plane, v of the torus) with
 * u1 - u0 >= 2 pi is the full turn and is never clipped. */
typedef struct {
    cb_ssi_surface_kind kind;
    cb_analytic_surface analytic;
    double range[4];
    const cb_nurbs_surface_struct *nurbs;
} cb_ssi_surface;

void cb_ssi_surface_set_analytic(cb_ssi_surface *S, const cb_analytic_surface *a,
                                 const double range[4]);
void cb_ssi_surface_set_nurbs(cb_ssi_surface *S, const cb_nurbs_surface_t s);

/* ---------------------------------------------------------------- options ------------------ */

typedef struct {
    double tol;   /* every output point is within tol of each surface; <= 0: 1e-6 times the
                     model size (diagonal of the box of both control nets) */
    double chord; /* largest distance of a polyline chord's midpoint from the curve (sagitta);
                     <= 0: 1e-3 times the model size */
    int threads;  /* patch pairs run on at most this many threads (0: all, 1: serial) */
    slong max_phi_degree; /* pairs whose phi has a degree in s or t above this (its true
                             bidegree, computed exactly) do not run the topology stage: a
                             B-spline pair takes the subdivision route, an analytic/B-spline
                             pair too, its analytic side written as its exact rational
                             B-spline (_cb_ssi_analytic_as_nurbs); default 12, the bidegree a
                             torus gives with a bicubic patch; the paper's Example 2 needs 27
                             (about 6 s) */
    cb_ctopo_opts topo;   /* passed to cb_ctopo_compute; defaults of cb_ctopo_opts_default */
    int spline_max_depth; /* subdivision route: sub-patches are not split below parameter
                             width 2^-spline_max_depth of their Bezier patch; default 30 (the
                             3D floor, tol / 8, usually stops them first) */
    slong spline_max_subpairs; /* subdivision route: sub-patch pairs examined per Bezier
                                  patch pair before the rest is reported uncertified;
                                  default 20000 */
    slong spline_band_subpairs; /* subdivision route: a Bezier pair that ran out of that
                                   budget runs again with this one, sub-pairs proved within
                                   tol of each other left whole at any size (a contact band
                                   along a tangential curve, then traced: ssi/README.md,
                                   "Outcomes"), kept when it leaves nothing uncertified;
                                   default 200000; 0: no second run */
    int recognise; /* 1 (default): B-spline faces proved to lie on planes, cylinders, spheres
                      or cones (within 1e-3 tol) take the analytic closed forms when one
                      decides the pair (ssi_recog.c); 0: always the B-spline routes */
    const cb_context *cancel; /* NULL (default), or a context whose cancellation
                                 (cb_context_cancel) cb_ssi_bodies checks before each face
                                 pair: it then stops with CB_ERR_CANCELLED */
    cb_context *progress; /* NULL (default), or a context whose progress callback
                             cb_ssi_bodies calls with the face pairs done out of those to run
                             (stage "ssi"; pairs differ widely in cost) */
    int keep_marks; /* 0 (default); 1: r->mark gets the vertices of the certified topology
                       graphs (cb_ssi_mark), for pictures; costs a little memory per pair */
    int topo_transpose; /* 1 (default): a patch pair whose curve topology is refused as not in
                           generic position (several multiple roots over one irrational
                           critical value of Q's first parameter) is tried again sweeping
                           along Q's second parameter; 0: not */
} cb_ssi_opts;

void cb_ssi_opts_default(cb_ssi_opts *o);

/* ---------------------------------------------------------------- result ------------------- */

typedef struct {
    double xyz[3];
    double uv_a[2]; /* parameters on A */
    double uv_b[2]; /* parameters on B */
} cb_ssi_point;

/* The three outcomes of every decision the SSI makes (per patch pair, per curve, per
 * coincidence record; ssi/ssi_tol.h lists the rules):
 *   CB_SSI_CERTIFIED   proved: exact or interval arithmetic, or a closed form decided on the
 *                      exact descriptions by the rule of ssi_tol.h (CB_SSI_CLOSED_FORM_*);
 *   CB_SSI_WITHIN_TOL  not separated by the certified routes, but proved to lie within tol
 *                      (a region of 3D size at most tol, or surfaces within tol of each other
 *                      over a region); resolved by a stated rule and listed in r->region;
 *   CB_SSI_REFUSED     neither: listed in r->failed with the reason (and the region when
 *                      known). */
typedef enum { CB_SSI_CERTIFIED = 0, CB_SSI_WITHIN_TOL = 1, CB_SSI_REFUSED = 2 } cb_ssi_outcome;

/* "certified", "within_tolerance", "refused". */
const char *cb_ssi_outcome_name(cb_ssi_outcome o);

/* A maximal intersection curve: a polyline whose points all lie within tol of both surfaces.
 * closed: the last point equals the first (stored twice). Curves that meet at a node share
 * that end point exactly. tangential: the surfaces touch along the whole curve (it lies on a
 * repeated factor of phi). certified: 1 when every piece comes from a certified patch pair and
 * every join of two pieces follows from the certified graphs (the same boundary root of a
 * shared patch side, ssi_stitch.c); 0 when some join was resolved within tolerance, or a piece
 * was (a contact band's valley, a side lying on the other surface's side); its region is in
 * r->region. */
typedef struct {
    slong n;
    cb_ssi_point *pt;
    int closed, tangential;
    int face_a, face_b; /* faces of cb_ssi_bodies; -1 for cb_ssi_surfaces */
    int certified;
} cb_ssi_curve;

/* An isolated intersection point: always a contact of the two surfaces (tangential = 1).
 * certified as for curves (0: merged with another within tolerance). */
typedef struct {
    cb_ssi_point p;
    int tangential;
    int face_a, face_b;
    int certified;
} cb_ssi_isolated;

/* A patch pair that could not be certified: its result is missing from the output. Patch
 * indices are those of cb_nurbs_surface_extract_bezier (-1 for an analytic side). */
typedef struct {
    int face_a, face_b;
    int patch_a, patch_b;
    cb_status status;
    char msg[200];
    int has_box;            /* box_a, box_b are set: the uncertified region of the pair */
    double box_a[4], box_b[4]; /* {u0, u1, v0, v1} in the surfaces' parameters */
} cb_ssi_failure;

/* Two faces (surfaces) that lie on one surface, so that they share a 2D region or could: no
 * curve is output for them (their common boundary is the trimming of one face by the other,
 * the Boolean stage's business). One record per call of cb_ssi_surfaces (per face pair in
 * cb_ssi_bodies) in which some patch pair was proved to lie on one surface. Never decided by
 * samples (samples only choose which pairs try a proof, ssi/ssi_coincide.c):
 *   a patch pair of the algebraic route: phi = F(Q) identically zero (exact), or, within tol,
 *     a rigorous bound: max |phi| over Q's patch from its Bernstein coefficients over the
 *     least weight, divided by a ball-arithmetic lower bound of |grad F| over Q's hull grown
 *     by tol, at most tol (every point of Q's patch within tol of F = 0);
 *   a patch pair of the subdivision route: Q's patch is P's polynomial (or rational) map
 *     continued over a box of its parameters, exactly, or within tol by the control points of
 *     the difference (exact rational arithmetic, no rounding);
 *   analytic/analytic (closed forms, CB_SSI_CLOSED_FORM_* of ssi_tol.h): the same surface by a
 *     comparison of the descriptions (same kind; planes: normals parallel within tol / size and
 *     offset within tol; cylinders, cones, tori, spheres: axis, centre or apex and radii within
 *     tol); exact when the two exact implicit equations are proportional. Other analytic pairs
 *     (ellipsoids) take the general route and its proofs.
 * exact: 1 when every patch pair of the record was proved to lie exactly on one surface
 * (outcome certified); 0 when some was proved only within tol (outcome within_tolerance, its
 * region listed in r->region); width: the largest proved distance bound (0 when exact).
 * The records do not say whether the faces' regions overlap: two disjoint discs of one plane
 * are listed too. Orientation: same_normal = 1 when the surface normals S_u x S_v of A and B
 * point the same way at xyz (a point of both), 0 when they are opposite; same_face_normal is
 * the same comparison for the face normals (S_u x S_v times the face's same_sense: -1 when 0),
 * filled by cb_ssi_bodies (equal to same_normal for cb_ssi_surfaces). */
typedef struct {
    int face_a, face_b;
    int patch_a, patch_b; /* the patch pair whose normals were compared (-1: analytic side) */
    slong patch_pairs;    /* patch pairs of the two surfaces found on one surface */
    int whole;            /* 1: every patch pair examined (not culled) lies on one surface;
                             0: some did not, and their curves are output as usual */
    int same_normal, same_face_normal;
    double xyz[3];
    int exact;            /* 1: proved exactly (certified); 0: within tol (within_tolerance) */
    double width;         /* largest proved distance of Q's patch from P's surface; 0 exact */
} cb_ssi_coincident;

/* A region resolved within tolerance (outcome CB_SSI_WITHIN_TOL):
 *   COINCIDENCE  a patch pair proved to lie within width (<= tol) of one surface, not exactly;
 *   NEAR_NODE    curve ends that the certified graphs could not tell apart or join (several
 *                candidates within their bounds on a patch side, or ends on no side) whose 3D
 *                box has diameter width <= tol: joined at one node (the first end's point);
 *   CONTACT_BAND surfaces proved within tol of each other over a region wider than tol, width
 *                its diameter (the subdivision route's tangent regions): branch ends joined at
 *                one point of it (a near-tangent node, cusp or touching point; above 1000 tol
 *                along the zero set of the distance), a tangential curve traced along it (the
 *                valley of the distance), or one isolated contact point;
 *   SIDE         a side of a patch of A lying on a side of a patch of B (two faces sharing an
 *                edge): the curve along it is that side, its points within width (<= tol / 2,
 *                proved) of both surfaces; boundary roots within tol / 2 of it on the sides
 *                across are taken as its crossings of them (the subdivision route);
 *   OUTSIDE_FACE not within tolerance, and not a refusal: a patch pair's region the routes left
 *                uncertified (the boxes of its sub-pairs), proved to lie outside face A's or
 *                face B's trimmed domain and away from its boundary (cb_ssi_bodies: its
 *                centre outside the loops, no loop within its bound of the box, the surface
 *                over it farther than tol plus the edges' tolerances from the boundary edges),
 *                so no curve of the two faces lies in it; lo, hi the box of that surface over
 *                it, width 0.
 * Parameter boxes {u0, u1, v0, v1} in A's and B's parameters (patch indices -1 for an analytic
 * side or when several patches are involved); lo, hi the 3D box. */
typedef enum {
    CB_SSI_REGION_COINCIDENCE = 0,
    CB_SSI_REGION_NEAR_NODE = 1,
    CB_SSI_REGION_CONTACT_BAND = 2,
    CB_SSI_REGION_SIDE = 3,
    CB_SSI_REGION_OUTSIDE_FACE = 4
} cb_ssi_region_kind;

/* "coincidence", "near_node", "contact_band", "side", "outside_face". */
const char *cb_ssi_region_kind_name(cb_ssi_region_kind k);

typedef struct {
    cb_ssi_region_kind kind;
    int face_a, face_b;
    int patch_a, patch_b;
    double box_a[4], box_b[4];
    double lo[3], hi[3];
    double width;
} cb_ssi_region;

/* A vertex of the certified topology graph of one patch pair of the algebraic route (see
 * cb_ctopo_vertex_struct), kept with opts.keep_marks to show what the topology stage decided:
 * critical points (folds, nodes, cusps), regular points on critical lines (FIBRE), helping
 * points, points on the patch box's sides and isolated points. The graph lives in the Bezier
 * patch of the parameterised side Q; uv are that surface's parameters, mapped as the curves'
 * points are. Pairs of the subdivision route and of the closed forms have no graph and give
 * no marks; a vertex on a side shared by two patches is listed by each pair that has it. */
typedef struct {
    int face_a, face_b;
    int q_side;   /* the surface whose parameters uv are: 0 A, 1 B */
    int patch;    /* Q's Bezier patch (cb_nurbs_surface_extract_bezier order); -1 when Q is
                     an analytic surface's exact rational form (the general route) */
    cb_ctopo_kind kind;
    int singular, tangential; /* as in cb_ctopo_vertex_struct */
    double uv[2];
    double xyz[3]; /* Q(uv) */
} cb_ssi_mark;

typedef struct {
    slong n_curves, alloc_curves;
    cb_ssi_curve *curve;
    slong n_points, alloc_points;
    cb_ssi_isolated *point;
    slong n_failed, alloc_failed;
    cb_ssi_failure *failed;
    slong n_coincident, alloc_coincident;
    cb_ssi_coincident *coincident;
    slong n_marks, alloc_marks; /* only with opts.keep_marks; in patch-pair order */
    cb_ssi_mark *mark;
    slong n_regions, alloc_regions; /* regions resolved within tolerance, in pair order */
    cb_ssi_region *region;

    cb_status status;       /* CB_OK when nothing was refused (every patch pair certified or
                               resolved within tolerance), else the status of the first
                               failure (in pair order), or CB_ERR_NOMEM when that failure
                               could not be listed in failed */
    /* Outcomes: every patch pair that is not culled is counted in exactly one of
     * pairs_certified, pairs_within_tolerance and pairs_outside_face, or has a record in
     * failed (refused; failed
     * also lists ambiguous joins between pairs and face pairs the driver does not take). */
    slong pairs_total;      /* patch pairs considered */
    slong pairs_culled;     /* separated oriented boxes (section 4.1) */
    slong pairs_empty;      /* phi proved sign-definite by its Bernstein coefficients */
    slong pairs_certified;  /* topology computed, or exact coincidence (includes pairs_empty) */
    slong pairs_within_tolerance; /* resolved within tolerance: coincident within tol, or a
                                     join of its curves' ends decided so (r->region) */
    slong pairs_outside_face; /* cb_ssi_bodies: patch pairs whose uncertified region lies
                                 outside one of the trimmed faces (one region record
                                 CB_SSI_REGION_OUTSIDE_FACE each); their curves in the faces
                                 are certified */
    slong pairs_subdivided; /* patch pairs taken by the subdivision route (a subset of
                               pairs_total; certified ones are counted in pairs_certified) */
    slong subpairs;         /* sub-patch pairs the subdivision route examined */
    slong pairs_coincident; /* patch (or analytic surface) pairs found on one surface; counted
                               in pairs_certified (exact) or pairs_within_tolerance */
    slong pairs_closed_form; /* analytic/analytic pairs decided by a closed form (counted in
                                pairs_certified; the others took the general route) */
    slong regions_within_tol; /* tangent regions the subdivision route resolved within the
                                 tolerance (a cluster of sub-pairs of 3D diameter <= tol, or
                                 <= 1000 tol where the surfaces are proved within tol of each
                                 other): each became one point (_cb_ssi_tiny_resolve) */
    slong nodes_within_tol;   /* of them with branch ends joined there (near-tangent nodes);
                                 the others are isolated contact points */
    double width_within_tol;  /* largest 3D diameter of such a region */
    double tol;             /* tolerance used */
    double max_dist_a, max_dist_b; /* largest distance of an output point to A and to B */
    double time_topo, time_trace;  /* seconds summed over patch pairs (all threads) */
} cb_ssi_result_struct;
typedef cb_ssi_result_struct cb_ssi_result_t[1];

void cb_ssi_result_init(cb_ssi_result_t r);
void cb_ssi_result_clear(cb_ssi_result_t r);

/* ---------------------------------------------------------------- drivers ------------------ */

/* Intersection of A and B (whole surfaces; an analytic one restricted to its range), appended
 * to r with face_a = face_a, face_b = face_b (pass -1, -1 outside a body). Supported pairs:
 * analytic/NURBS either way round, NURBS/NURBS (the side of lower patch bidegree product is
 * implicitised per patch; a planar patch by its exact plane), analytic/analytic (closed forms
 * or the general route, see above; at most one of the two may have an unbounded range: it is
 * limited to the other's box; both unbounded is CB_ERR_INVALID). Curves of the closed forms are
 * clipped to both ranges with a slack of 1e-12 times the size (a curve on a range's end is
 * kept) and pieces shorter than 10 tol are dropped. Returns CB_OK even when some patch pairs
 * are not certified (see r->status and r->failed; a pair that ran out of memory is one of them,
 * with CB_ERR_NOMEM); an error return for invalid input leaves r's earlier content and adds
 * nothing, while CB_ERR_NOMEM (no room for the output itself, or for a failure record) may
 * leave part of this pair's output in r, which is then only good for clearing. The counters of
 * r are added to. */
cb_status cb_ssi_surfaces(cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B,
                          int face_a, int face_b, const cb_ssi_opts *opts, cb_error *err);

/* Every face of a against every face of b whose boxes overlap (AABB of the surface geometry
 * over the face's parameter box, grown by the tolerance). Analytic faces are bounded by the
 * parameter box of their edges (sampled and inverted); faces of revolution and extrusion by
 * the box of their pcurves (or of their edges inverted, where a coedge has no pcurve reaching
 * its edge), a B-spline profile by its domain, and intersected as the exact rational B-spline
 * of their surface over that box (cb_topo_surface_to_nurbs, arcs with cos(pi / 4) rounded):
 * every parameter the result gives for such a face (curve and isolated points, marks, the
 * boxes of regions and failures) is mapped back to the face's own surface
 * (cb_topo_surface_nurbs_param, a bijection of the B-spline's domain onto the box, strictly
 * increasing in each direction, so a certified topology stays certified), and its patch
 * indices are -1. A B-spline face whose pcurves agree with its edges is intersected as the part of
 * its surface over the box of its pcurves grown by a quarter of its width (not past the knot lines
 * around it), cut out exactly (same parameters; patch indices those of the whole surface's patches
 * holding them), and its box for the overlap test is the surface's over the pcurves' box: parts of
 * a surface outside its face are not intersected (a curve leaving that part ends on its cut,
 * outside the face). The curves are not clipped to trimming loops. Face pairs that cannot be
 * intersected (a face that could not be bounded or converted) are listed in r->failed with
 * patch indices -1. Coincident face pairs get same_face_normal from the faces'
 * same_sense. With opts->tol <= 0 the tolerance is 1e-6 times
 * the diagonal of the box of both bodies. Face pairs run in parallel on opts->threads (each
 * serial inside) and are combined in face-pair order. */
cb_status cb_ssi_bodies(cb_ssi_result_t r, const cb_topo_body *a, const cb_topo_body *b,
                        const cb_ssi_opts *opts, cb_error *err);

/* ------------------------------------------- for the driver's own files (not a public API) -- */

/* A point of a piece under construction: the parameters on P and Q (the implicitised and the
 * parameterised side) and which of them are held fixed during refinement (bit 0 u, 1 v, 2 s,
 * 3 t): a point on a patch boundary keeps that boundary's parameter. */
typedef struct {
    double uv[2], st[2];
    unsigned fixed;
} _cb_ssi_pq;

/* A boundary root known exactly: the end's free coordinate along a Q patch side (local, in
 * [0, 1]) is the only root of p in [lo, hi] (lo == hi: exactly lo, whatever p). p is the
 * primitive part of the certified graph's squarefree h restricted to that side, so two ends on
 * one side of Q's patches (or on the shared side of two neighbours, whose boundary curves are
 * bitwise the same) are the same point iff gcd of their p has a root in both intervals
 * (ssi_stitch.c). NULL p: only exact points (lo == hi) compare. */
typedef struct {
    fmpz_poly_struct *p;
    fmpq_t lo, hi;
} _cb_ssi_side_root;

/* A patch-boundary line through a piece's end: parameter dir of surface sigma (0 P, 1 Q) fixed
 * to c, the piece on the side half (+1: parameters >= c, -1: <= c) of it, and an enclosure
 * [lo, hi] of the end's free parameter along the line: certified (the graph's vertex interval,
 * the subdivision route's Krawczyk enclosure) or derived from the refinement (CB_SSI_SPLIT_*
 * of ssi_tol.h, where the clipping split the curve on P's side). c, lo, hi are local until
 * mapped to the surfaces' domains with the piece's points; range is the free parameter's range
 * of the patch (domain), under which local coordinates of two ends compare. root: exact data
 * (Q sides of the algebraic route) or NULL. */
typedef struct {
    int sigma, dir, half;
    double c, lo, hi;
    double range[2];
    _cb_ssi_side_root *root;
} _cb_ssi_end_line;

/* How a piece ends: vid >= 0 is a vertex of its pair's certified topology graph (ends with the
 * same vid in one pair are one point, with different vids different points); nl lines it lies
 * on (a corner of a patch box: two); region (below). */
typedef struct {
    slong vid;
    int nl;
    _cb_ssi_end_line ln[2];
    slong region; /* >= 0: moved onto the point of that tangent region resolved within the
                     tolerance (_cb_ssi_tiny_resolve); ends with one region are one node */
} _cb_ssi_end;

/* A polyline found in one patch pair, before stitching; points in P/Q parameters. */
typedef struct {
    slong n, alloc;
    _cb_ssi_pq *pt;
    double *xyz;   /* 3 n: midpoints of P(uv) and Q(st) */
    double gap;    /* largest |P(uv) - Q(st)| over the points */
    int closed, tangential, isolated;
    int within; /* a curve within tolerance: the valley of a contact band (ssi_band.c), or
                   side below */
    int side;   /* a piece of a side of P lying on a side of Q (_cb_ssi_coside) */
    _cb_ssi_end end[2]; /* first and last point (an isolated point: end[0]) */
} _cb_ssi_piece;

/* An end that is on no line and no vertex. */
void _cb_ssi_end_init(_cb_ssi_end *e);
/* Frees the exact roots of e's lines. */
void _cb_ssi_end_clear(_cb_ssi_end *e);
/* Adds a line to e (at most two; a third is ignored); the line's root is NULL. */
_cb_ssi_end_line *_cb_ssi_end_add_line(_cb_ssi_end *e, int sigma, int dir, int half, double c,
                                       double lo, double hi);

void _cb_ssi_piece_init(_cb_ssi_piece *p);
void _cb_ssi_piece_clear(_cb_ssi_piece *p);
/* Appends a point; CB_ERR_NOMEM leaves p as it was. */
cb_status _cb_ssi_piece_push(_cb_ssi_piece *p, const _cb_ssi_pq *q, const double X[3]);

typedef struct {
    slong n, alloc;
    _cb_ssi_piece *p;
} _cb_ssi_piece_set;

void _cb_ssi_piece_set_init(_cb_ssi_piece_set *ps);
void _cb_ssi_piece_set_clear(_cb_ssi_piece_set *ps);
/* A new empty piece at the end of ps; NULL when out of memory (ps is left as it was). */
_cb_ssi_piece *_cb_ssi_piece_set_add(_cb_ssi_piece_set *ps);

/* A curve in Q's local patch box [0,1]^2 from the tracer: sigma, tau per point, and the
 * Q-side fixed bits of each point (bit 2 s, bit 3 t) for points on the box sides. v: the graph
 * vertices it starts and ends at (-1 for a closed curve; an isolated point: both its vertex). */
typedef struct {
    slong n, alloc;
    double *st;
    unsigned *fixed;
    int closed, tangential, isolated;
    slong v[2];
} _cb_ssi_trace_curve;

/* The traced curves of one patch pair. */
typedef struct {
    slong n, alloc;
    _cb_ssi_trace_curve *c;
} _cb_ssi_trace_set;

void _cb_ssi_trace_set_init(_cb_ssi_trace_set *ts);
void _cb_ssi_trace_set_clear(_cb_ssi_trace_set *ts);

/* The squarefree part of phi without its content in t, as doubles for tracing: hd[i (dt+1)
 * + j] multiplies s^i t^j, scaled so that the largest is about 1. _cb_ssi_sqf_set takes it
 * from the topology graph (cb_ctopo_struct.h), which has made it already: CB_OK or
 * CB_ERR_NOMEM (hd then NULL). */
typedef struct {
    slong ds, dt;
    double *hd;
} _cb_ssi_sqf;

void _cb_ssi_sqf_init(_cb_ssi_sqf *h);
void _cb_ssi_sqf_clear(_cb_ssi_sqf *h);
cb_status _cb_ssi_sqf_set(_cb_ssi_sqf *h, const cb_bipoly_struct *hp);

/* Sharpens the double t of the vertices of T whose certified t-box is not a point (the topology
 * stage leaves such boxes as wide as their certification needed, up to a quarter of the box):
 * a simple root by bisection of h(s, .) over the box (it changes sign once there); a multiple
 * one (fold, cusp, isolated point) by bisection of h_t, or golden-section search for the least
 * |h| when h_t keeps its sign. The tracer starts and ends edges at these coordinates; a vertex
 * left at its box's midpoint put a spike into curves whose branch is steep there. */
void _cb_ssi_vertex_refine(cb_ctopo_t T, const _cb_ssi_sqf *h);

/* Sorted distinct real roots of sum_j a[j] t^j (j <= deg) in [0, 1], at most deg of them
 * (none for a constant). Method: the roots of the derivative (recursively) cut [0, 1] into
 * monotone pieces; a piece holds a root where its end values change sign (bisection to
 * round-off) or vanish exactly. Never divides by the leading coefficient, so a degree drop
 * where it vanishes does no harm. */
int _cb_ssi_roots01(double *roots, const double *a, int deg);

/* Geometry of Q for the tracer's step control: point of Q at local (sigma, tau). */
typedef void (*_cb_ssi_lift_fn)(double X[3], const void *ctx, double sigma, double tau);

/* Traces every edge of the topology graph T of the curve h = 0 in [0,1]^2 and joins edges
 * through vertices of degree 2 not on a side of the box into curves; isolated vertices become
 * one-point curves. Step control: the 3D midpoint of every chord (lifted by lift) is within
 * chord of the curve's midpoint and chords are at most max_seg long. Method: on an edge
 * between consecutive vertices, h(s, .) has the same number of roots in [0, 1] for every s
 * strictly between them (no critical value there), so the branch is the root of a fixed rank;
 * the rank is read at the edge's regular end point and kept, which is what makes jumping to
 * another branch impossible. Vertical edges are sampled along t. CB_ERR_NOMEM may leave out
 * with part of the curves. */
cb_status _cb_ssi_trace(_cb_ssi_trace_set *out, const cb_ctopo_t T, const _cb_ssi_sqf *h,
                        _cb_ssi_lift_fn lift, const void *lift_ctx, double chord,
                        double max_seg);

/* The two sides of one patch pair, in local parameters: [0,1]^2 for Bezier patches (mapped
 * to the surfaces' domains only in the output), the own parameters for an analytic P. */
typedef struct {
    int p_analytic;
    cb_analytic_surface an;
    double an_range[4], an_period[2]; /* period 0: not angular */
    const cb_dixon_patch_struct *p;        /* P's Bezier patch when !p_analytic */
    const cb_dixon_pencil_struct *p_pencil; /* its Dixon pencil; NULL for a planar patch */
    const cb_dixon_patch_struct *q;        /* Q's Bezier patch */
    int p_polynomial; /* P's Bezier patch has equal weights; p_net is then the box of its
                         control points */
    cb_aabb p_net;
    double tol, chord, max_seg;
    double size; /* the model size (diagonal of both surfaces' boxes) */
} _cb_ssi_pair_geom;

/* Parameters of a point X on the analytic surface a, by the closed forms of its
 * parameterisation in the local frame; angles in (-pi, pi]. */
void _cb_ssi_analytic_invert(double uv[2], const cb_analytic_surface *a, const double X[3]);

/* Q(sigma, tau) for the tracer (ctx is the _cb_ssi_pair_geom). */
void _cb_ssi_lift(double X[3], const void *geom, double sigma, double tau);

/* Lifts the traced curves of one pair, refines every point onto both surfaces and clips to
 * P's parameter box (section 4.4): curves are split where P's parameters cross the box's
 * boundary, the split points refined onto that boundary, and a piece is kept when its
 * representative (middle) point lies inside: for a spline P decided by the Dixon inversion
 * cb_inversion_solve, for an analytic P by its own parameters. Points are refined by
 * Gauss-Newton with minimum-norm steps on P(u, v) = Q(s, t), parameters on patch sides held
 * fixed, until |P - Q| <= tol / 100 or no progress; the point reported is the midpoint.
 * CB_ERR_NOMEM may leave out with part of the pieces (each of them whole). */
cb_status _cb_ssi_clip(_cb_ssi_piece_set *out, const _cb_ssi_trace_set *ts,
                       const _cb_ssi_pair_geom *g);

/* The exact side roots of the ends of pieces ps->p[first..] that are vertices of T on the
 * box sides (T, the graph of phi = 0 in Q's local [0,1]^2, phi in the variables (s, t) of ctx
 * as the topology took it; swap: T's s is Q's second parameter): a line per side with the
 * vertex's certified interval and phi restricted to the side (the squarefree h where the side
 * is a vertical line of phi). CB_ERR_NOMEM. */
cb_status _cb_ssi_ends_from_graph(_cb_ssi_piece_set *ps, slong first, const cb_ctopo_t T,
                                  const fmpz_mpoly_t phi, const fmpz_mpoly_ctx_t ctx, int swap);

/* The pieces of one patch pair for stitching: patch indices (A's, B's; -1 analytic) for the
 * records of joins involving them, the patches' boxes (for curves along their sides), and, on
 * return, the outcome of the joins of their ends
 * (CB_SSI_CERTIFIED, or CB_SSI_WITHIN_TOL / CB_SSI_REFUSED when a join touching them was
 * resolved within tolerance / refused). */
typedef struct {
    const _cb_ssi_piece_set *ps;
    int patch_a, patch_b;
    double pdom[4], qdom[4]; /* P's and Q's patch boxes in the domains (NAN: analytic P) */
    cb_ssi_outcome outcome;
} _cb_ssi_stitch_set;

typedef struct {
    int swapped;          /* P is B (uv goes to uv_b) */
    int face_a, face_b;
    double tol, chord;
    int closed_form;      /* pieces of the closed forms: joined by CB_SSI_CLOSED_FORM_JOIN */
    /* seam[sigma][dir] = {lo, hi}: the sides lo and hi of P's (0) or Q's (1) domain in
     * direction dir are one curve (a closed B-spline whose first and last control rows are
     * equal up to one power-of-two factor: exactly the same points), so ends on them are on
     * one line; NAN where not. */
    double seam[2][2][2];
} _cb_ssi_stitch_opts;

/* seam[dir] = {lo, hi} of the B-spline s's domain when its first and last control rows in
 * direction dir are the same homogeneous points up to one power-of-two factor, else NAN. */
void _cb_ssi_seams(double seam[2][2], const cb_nurbs_surface_struct *s);

/* Joins the pieces of all patch pairs (sets, in pair order; parameters already in the
 * surfaces' domains) into maximal curves appended to r. Nodes, never by distance alone
 * (ssi/ssi_tol.h names each rule and its outcome):
 *   1. ends with the same graph vertex of one pair are one node;
 *   2. ends on one patch-boundary line (P's or Q's, in the domains; the two end sides of an
 *      exactly closed B-spline are one line) whose enclosures overlap form a candidate group;
 *      in it, ends are the same point when certified so (the same vertex; exact side roots
 *      with a common root of their polynomials in both intervals; equal exact points) and
 *      different points when certified so (different vertices of one pair; no common root);
 *      what is left undecided is joined when it is one class on each side of the line (the
 *      bound-match), and otherwise the group is ambiguous: joined at one node within
 *      tolerance when its 3D box is at most CB_SSI_NEAR_NODE tol across (a NEAR_NODE region),
 *      refused (a failure record with the boxes) when larger;
 *   3. ends still alone and undecided (on no line, or with no candidate on it) joined with the
 *      ends of other pairs within CB_SSI_FREE_JOIN tol, as an ambiguous group;
 *   4. a piece whose points stay within CB_SSI_DEGENERATE_PIECE tol of its first is dropped and
 *      its ends made one node within tolerance, unless it has no extent at all and one end is
 *      a graph vertex already joined to another pair (dropped, nothing merged).
 * A node takes the coordinates of its first end. Chains pass nodes of degree 2. A piece
 * joining the same two nodes as an earlier one while both lie along one patch side (Q: the
 * side parameter held; P: within CB_SSI_ON_SIDE_EPS) is the same curve found by both
 * neighbours and dropped; an isolated point joined to a node or an earlier point too. Curves
 * through a node joined within tolerance have certified = 0; sets[k].outcome says whether a
 * join touching set k was made within tolerance or refused.
 * With o->closed_form: ends within CB_SSI_CLOSED_FORM_JOIN tol are one node, a piece that never
 * leaves its node is dropped, and a piece with the same nodes as an earlier one whose middle is
 * within chord + that of it is dropped (the closed forms' rule, certified as such). Curves
 * start at their lowest piece, so the output depends only on the order of sets. A curve's
 * folds (a stretch traced out and back, CB_SSI_FOLD) are dropped. CB_ERR_NOMEM may leave part
 * of the curves in r. */
cb_status _cb_ssi_stitch(cb_ssi_result_t r, _cb_ssi_stitch_set *sets, slong nsets,
                         const _cb_ssi_stitch_opts *o);

/* ------------------------------------------- the result container (ssi_result.c) ----------- */

/* Appends a coincidence record (patch_pairs 1, whole 1, same_face_normal = same_normal, exact,
 * width); NULL when out of memory (r is left as it was). */
cb_ssi_coincident *_cb_ssi_add_coincident(cb_ssi_result_t r, int fa, int fb, int pa, int pb,
                                          int same_normal, const double xyz[3], int exact,
                                          double width);

/* Appends a region; NULL when out of memory (r is left as it was). */
cb_ssi_region *_cb_ssi_add_region(cb_ssi_result_t r, cb_ssi_region_kind kind, int fa, int fb,
                                  int pa, int pb, double width);

/* Appends a new empty curve (face_a, face_b set, certified 1); NULL when out of memory. */
cb_ssi_curve *_cb_ssi_add_curve(cb_ssi_result_t r, int fa, int fb);

/* Appends a new isolated point (tangential 1, certified 1, face_a, face_b set); NULL when out
 * of memory. */
cb_ssi_isolated *_cb_ssi_add_point(cb_ssi_result_t r, int fa, int fb);

/* Appends n marks to r; CB_ERR_NOMEM leaves r as it was. */
cb_status _cb_ssi_add_marks(cb_ssi_result_t r, const cb_ssi_mark *m, slong n);

/* Appends everything s holds to r (curves, points, failures, coincidence records, regions,
 * marks; counters added, distances maxed) and leaves s without them. CB_ERR_NOMEM may have
 * moved part of s (a curve is then in r or in s, never both, so clearing both frees
 * everything once). */
cb_status _cb_ssi_result_move(cb_ssi_result_t r, cb_ssi_result_t s);

/* Distance from X to the B-spline surface pat (a Bezier patch or a whole surface), and the
 * parameters uv of the nearest point found: the nearest of a 9 x 9 grid of its domain (or uv
 * itself when warm), then Gauss-Newton clamped to the domain (at most 30 steps, each kept only
 * when the distance drops). An upper bound on the distance to the surface (ssi_pairs.c). */
double _cb_ssi_nurbs_project(double uv[2], const cb_nurbs_surface_struct *pat, const double X[3],
                             int warm);

/* Inserts, into curves c0 .. of r that are not tangential, points of the curve (on both
 * surfaces within tol / 16) between consecutive points whose chord's midpoint lies farther
 * than chord from it, until none does: the tracer bounds the sagitta within each patch pair,
 * but pieces joined across pairs, moved onto nodes or clipped may leave longer chords. -1
 * when out of memory (r unchanged but for curves already done). */
int _cb_ssi_result_densify(cb_ssi_result_t r, slong c0, const cb_ssi_surface *A,
                           const cb_ssi_surface *B, double chord, double tol);

/* Distances of an output point to both surfaces at its own parameters (an upper bound on its
 * distance to each), recorded in r->max_dist_a, max_dist_b. */
void _cb_ssi_result_measure(cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B,
                            const cb_ssi_point *p);

/* B-spline surfaces that lie on analytic ones (ssi_recog.c).
 * _cb_ssi_recognise: 1 when s is proved to lie within delta of a plane, cylinder, sphere or cone
 * (a candidate fitted to samples, then a Bernstein bound of its equation over every Bezier
 * patch of s: see ssi_recog.c); a is that surface, *dev the proved largest distance (<= delta),
 * range an analytic parameter range holding s's image (angular directions whole turns).
 * _cb_ssi_recognised_pair: when every B-spline side of A, B is recognised (delta a thousandth of
 * the tolerance) and the analytic pair is decided by a closed form without failures, appends
 * that result, clipped to the B-splines' domains and with their parameters (point inversion),
 * and sets *done; otherwise appends nothing (*done = 0) and the caller takes the B-spline
 * route. CB_ERR_NOMEM when r has no room for that result (part of it may be in r). */
int _cb_ssi_recognise(cb_analytic_surface *a, double range[4], double *dev,
                      const cb_nurbs_surface_struct *s, double delta);
cb_status _cb_ssi_recognised_pair(cb_ssi_result_t r, const cb_ssi_surface *A,
                                  const cb_ssi_surface *B, int face_a, int face_b,
                                  const cb_ssi_opts *opts, int *done, cb_error *err);

/* The B-spline an analytic surface stands for in _cb_ssi_analytic_pair_img: its inverter, and
 * the proved largest distance between the two. */
typedef struct {
    const cb_topo_inverter *inv;
    double dev;
} _cb_ssi_image;

/* Two analytic surfaces (ssi_analytic.c; see cb_ssi_surfaces). */
cb_status _cb_ssi_analytic_pair(cb_ssi_result_t r, const cb_ssi_surface *A,
                                const cb_ssi_surface *B, int face_a, int face_b,
                                const cb_ssi_opts *opts, cb_error *err);
/* Degree of the analytic surface's implicit equation: plane 1, torus 4, the quadrics 2
 * (ssi_analytic.c). */
int _cb_ssi_implicit_degree(const cb_analytic_surface *a);
/* An analytic/NURBS pair (either way round) whose phi, the analytic implicit equation of
 * degree N (plane 1, quadrics 2, torus 4) substituted into the B-spline's patches, would have a
 * degree above opts->max_phi_degree: the analytic side over its range (an unbounded direction
 * limited to the B-spline's box) written as its exact rational B-spline
 * (cb_analytic_to_nurbs_exact) and the pair run as NURBS/NURBS, where the subdivision route
 * takes the patch pairs of high degree; the analytic side's parameters, region boxes and
 * distances are its own again in the result (ssi_analytic.c). */
cb_status _cb_ssi_analytic_as_nurbs(cb_ssi_result_t r, const cb_ssi_surface *A,
                                    const cb_ssi_surface *B, int face_a, int face_b,
                                    const cb_ssi_opts *opts, cb_error *err);
/* The same where img[k] (may be NULL) is the B-spline that side k stands for: the curves are
 * clipped to that B-spline's image (its domain, by point inversion) instead of the analytic
 * range, their parameters on that side are the B-spline's, and only the closed forms run (a
 * pair they do not decide gives nothing). */
cb_status _cb_ssi_analytic_pair_img(cb_ssi_result_t r, const cb_ssi_surface *A,
                                    const cb_ssi_surface *B, const _cb_ssi_image *const img[2],
                                    int face_a, int face_b, const cb_ssi_opts *opts,
                                    cb_error *err);

/* Appends a failure record to r (ssi_result.c) and sets r->status to st if it was CB_OK.
 * CB_ERR_NOMEM when the record cannot be stored: r->status is then set to CB_ERR_NOMEM if it
 * was CB_OK, so r never reads as certified, and the caller must fail with CB_ERR_NOMEM, since a
 * failure missing from r->failed would otherwise go unseen by readers that count n_failed. */
cb_status _cb_ssi_add_failure(cb_ssi_result_t r, int fa, int fb, int pa, int pb, cb_status st,
                              const char *msg);

/* ------------------------------------------- coincidence proofs (ssi_coincide.c) ----------- */

/* q = the double x, exactly (a double is a dyadic rational). */
void _cb_fmpq_set_d(fmpq_t q, double x);

/* Whether Q's Bezier patch lies within tol of the surface F = 0, proved: 1 with *width the
 * proved bound (<= tol), 0 when no proof was found (the pair then takes the normal routes).
 * phi = F(Q) as cb_phi_compute gives it (not identically zero: that is the exact case, the
 * caller's); q: Q's patch (weights positive). Method: |F(X)| <= max |Bernstein coefficient of
 * phi| / (min weight)^N over the patch (phi = d^N F(X) for Q = (a, b, c, d) scaled), and
 * |grad F| >= g > 0 over Q's control box grown by tol in ball arithmetic (Taylor shift of F to
 * the box centre, remainder bounded by the shifted coefficients); then every point of Q is
 * within max |F| / g of F = 0 (the gradient flow from it reaches F = 0 within that length,
 * inside the grown box). Rounding: every quantity is an Arb ball, upper or lower bound taken. */
int _cb_ssi_coincide_implicit(double *width, const cb_implicit_struct *F, const cb_phi_struct *phi,
                              const cb_dixon_patch_struct *qd, const cb_nurbs_surface_struct *q,
                              double tol);

#endif
