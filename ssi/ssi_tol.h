/* ssi_tol.h — every rule of ssi/ in which a tolerance or a floating-point threshold takes part
 * in a decision about the intersection's topology or identity, named once, with the outcome the
 * result reports for it (cb_ssi_outcome, ssi.h). `grep CB_SSI_ ssi/ssi_tol.h` lists them.
 *
 * tol below is the SSI tolerance (cb_ssi_opts.tol; default 1e-6 times the model size), size the
 * diagonal of the box of both surfaces' control nets.
 *
 * Outcomes:
 *   certified          the decision is exact or interval arithmetic, or a closed form's
 *                      comparison of the exact analytic descriptions under the stated rule;
 *   within_tolerance   the rule resolved a region proved smaller than tol, or surfaces proved
 *                      within tol of each other there: listed in r->region;
 *   refused            r->failed, with the reason. */
#ifndef CB_SSI_SSI_TOL_H
#define CB_SSI_SSI_TOL_H

/* ---------------------------------------------------------------- coincidence ------------- */

/* Pre-filter of the coincidence proofs (ssi_coincide.c, ssi_pairs.c): a patch pair tries a
 * proof only when every point of a CB_SSI_COINCIDENT_GRID x CB_SSI_COINCIDENT_GRID grid of Q's
 * patch lies within CB_SSI_COINCIDENT_FILTER tol of P (first-order distance |F| / |grad F|, or
 * the projection onto P's continued patch). The samples never decide: a pair they pass that
 * the proof does not take goes through the normal routes, whose answer is certified. */
#define CB_SSI_COINCIDENT_GRID 5
#define CB_SSI_COINCIDENT_FILTER 1.0

/* Coincidence within tolerance: proved distance of every point of Q's patch from P's surface
 * at most CB_SSI_COINCIDENT_WIDTH tol (outcome within_tolerance, a COINCIDENCE region; exact
 * coincidence, phi = 0 or Q = P(A), is certified). */
#define CB_SSI_COINCIDENT_WIDTH 1.0

/* ---------------------------------------------------------------- stitching --------------- */

/* Ends of pieces are joined by the certified graphs (ssi_stitch.c): the same vertex of one
 * pair's graph; the same exact boundary root on a shared patch side (Q's sides in the algebraic
 * route: phi restricted to the side, a common root of the two polynomials in both certified
 * intervals; neighbouring Bezier patches share their boundary control points bitwise, and a
 * closed B-spline whose first and last control rows are the same points up to one power-of-two
 * factor has its two end sides identified as one). Where no exact data exists, two ends on one
 * shared side whose enclosures overlap, one on each side of it and no other candidate within
 * the enclosures, are joined (the bound-match): the enclosures are the subdivision route's
 * Krawczyk boxes (rigorous for the Bezier patches) or, for the clipping's split points on P's
 * sides, the floating-point bound below. Such joins count as certified. */

/* Bound on a split point's position along P's patch side (clip.c): the refinement leaves the
 * point at distance gap from the other surface Q, so the crossing of the side curve C with Q
 * lies within gap / |n_Q . C'| in C's parameter (first order); the bound taken is
 * CB_SSI_SPLIT_SAFETY times that, with gap at least CB_SSI_SPLIT_ROUND times the size (the
 * round-off of evaluating the patches). Floating point, not a proof. Where it exceeds the
 * patch's parameter range (Q tangent to the side curve) the end is on no side. */
#define CB_SSI_SPLIT_SAFETY 4.0
#define CB_SSI_SPLIT_ROUND 1e-13

/* An ambiguous group of ends on a patch side (several candidates within their enclosures, or
 * certified identities that contradict each other): joined at one node when its 3D box has a
 * diameter of at most CB_SSI_NEAR_NODE tol (within_tolerance, NEAR_NODE region), refused above
 * (a failure record with the box; its ends stay apart). */
#define CB_SSI_NEAR_NODE 1.0

/* Ends left alone by the rules above and not decided by them (on no side: a split point whose
 * refinement failed, or Q tangent to the side; or on a side with no candidate: a closed surface
 * whose seam closes only to round-off, as STEP files write them): joined with the ends of other
 * pairs within CB_SSI_FREE_JOIN tol of them (within_tolerance, NEAR_NODE region, refused when
 * those span more than CB_SSI_NEAR_NODE tol). */
#define CB_SSI_FREE_JOIN 1.0

/* A piece whose points all stay within CB_SSI_DEGENERATE_PIECE tol of its first one (a curve
 * through a corner of the patch grid, or touching a patch side, seen by a neighbouring pair as a
 * piece of round-off length) is dropped and its two ends made one node: within_tolerance, a
 * NEAR_NODE region with the piece's box. A piece of no extent at all (every point the same
 * double) with an end at a graph vertex that is already joined to another pair's ends is
 * dropped without merging anything: the curve runs on through that vertex without it. */
#define CB_SSI_DEGENERATE_PIECE 1.0

/* Two pieces joining the same two nodes are the same curve found by two neighbouring pairs
 * when both run along one patch side: of Q (its side parameter held exactly by the tracer and
 * the refinement) or of P (every point's parameter within CB_SSI_ON_SIDE_EPS of the side, in P's
 * local [0, 1] box: the clipping's own slack, clip.c PARAM_EPS). The later one is dropped.
 * Pieces joining the same nodes otherwise are kept (two branches forming a lens). */
#define CB_SSI_ON_SIDE_EPS 1e-10

/* A curve's polyline that leaves a point and comes back to it within CB_SSI_FOLD tol, every
 * point between within CB_SSI_FOLD_REACH tol of it and within CB_SSI_FOLD tol of the chord
 * from it to the farthest of them, that one farther than CB_SSI_FOLD tol, is a fold: a stretch
 * traced out and back, an excursion of no area that no curve of two surfaces makes (seen where
 * a plane holds a B-spline's patch sides collapsed to a pole, an ellipsoid halved through its
 * poles, and on B-spline tori halved through their axis). The fold is dropped (ssi_stitch.c,
 * drop_folds); the curve's topology and outcome are unchanged. */
#define CB_SSI_FOLD 1.0
#define CB_SSI_FOLD_REACH 1000.0

/* ---------------------------------------------------------------- tangent regions --------- */

/* The subdivision route's tangent regions (spline_pair.c, kept there beside the code that
 * uses them): sub-pairs it cannot certify are not split below TINY_TOL tol in 3D, or STOP_TOL
 * tol where proved within tol of each other (slab); a cluster of them is resolved within the
 * tolerance when at most tol across (a NEAR_NODE region), or at most WT_MAX_TOL tol with every
 * member proved within tol (a CONTACT_BAND region): the piece ends in it moved onto one point
 * and joined there (within_tolerance; ssi_pairs.c lists the regions). A larger cluster, every
 * member proved within tol, holding no piece end, is a CONTACT_BAND whose curves are the valley
 * of the distance (ssi_band.c: every point within tol of both surfaces and in a member's box
 * grown by tol, every member's valley point within 2 chord + 10 tol of a curve, steps no
 * shorter than 4 tol; within_tolerance, the curves not certified). Such a cluster holding
 * piece ends, or where no valley is traced, is one node (ssi_band.c _cb_ssi_band_node: the ends
 * joined to it along the zero set of the distance, every point within tol of both surfaces;
 * with no end an isolated contact point; a CONTACT_BAND region). Other clusters are
 * refused. A cluster that no branch reaches or crosses is an isolated contact point, unless
 * within WT_MAX_TOL tol of a region branch ends moved into (a pocket beside a cusp's or node's
 * region: part of it) or of a wider such cluster (one contact cut in two). A Bezier pair's
 * first run stops once one of its clusters is wider than WT_MAX_TOL tol (TINY_CHECK) and runs
 * again as the band run (ssi_pairs.c). */

/* ---------------------------------------------------------------- sides on each other ----- */

/* A side of one Bezier patch lying on a side of the other (spline_side.c, _cb_ssi_coside: two
 * faces sharing an edge; the boundary classes of bench_ssi_corpus): taken as a curve of the
 * intersection when the Bernstein coefficients of the two sides' difference over their common
 * range (paired affinely) are within CB_SSI_COSIDE_WIDTH tol. Then the sub-pairs along it do
 * not search that side for boundary roots, nor the strips of the sides across it within
 * CB_SSI_COSIDE_STRIP tol of it in 3D (a root there is the side curve's crossing), and a
 * sub-pair along it without a proved direction whose sub-patches are proved within tol of
 * each other and have no other boundary root has the side's piece for all of its intersection
 * (flagged tangential). within_tolerance (a SIDE region per patch pair; the curves not
 * certified). */
#define CB_SSI_COSIDE_WIDTH 0.5
#define CB_SSI_COSIDE_STRIP 0.5

/* ---------------------------------------------------------------- closed forms ------------ */

/* Analytic/analytic closed forms (ssi_analytic.c) decide special positions on the exact
 * descriptions with tol for distances and tol / size for directions: parallel, coaxial, tangent
 * (contact lines placed halfway), the same surface. Their curves are certified under this rule
 * (a comparison of exact descriptions, as a B-rep decides that faces touch); a coincidence is
 * exact (certified) when the two exact implicit equations (cb_implicit_from_analytic) are equal,
 * within_tolerance (a COINCIDENCE region of width tol) otherwise. Ends of their pieces within
 * CB_SSI_CLOSED_FORM_JOIN tol are one node (and a piece between the same nodes as an earlier one
 * whose middle is within chord + that of it is dropped); pieces shorter than
 * CB_SSI_CLOSED_FORM_SHORT tol (a curve grazing a range's end) are dropped; the ranges are
 * clipped with a slack of CB_SSI_CLOSED_FORM_SLACK times the size (a curve on a range's end is
 * kept), the margin function sampled at CB_SSI_CLOSED_FORM_SAMPLES parameters (sign changes
 * bisected, local extrema searched for dips). B-spline planes, cylinders and spheres
 * recognised as exact rational forms (ssi_recog.c, control points within CB_SSI_RECOGNISE tol)
 * take these closed forms under the same rule; a coincidence found so is exact only when the
 * two B-splines are the same net, within_tolerance otherwise. */
#define CB_SSI_CLOSED_FORM_JOIN 1.0
#define CB_SSI_CLOSED_FORM_SHORT 10.0
#define CB_SSI_CLOSED_FORM_SLACK 1e-12
#define CB_SSI_CLOSED_FORM_SAMPLES 256
#define CB_SSI_RECOGNISE 1e-3

/* ---------------------------------------------------------------- not yet reported -------- */

/* Thresholds still deciding without an outcome of their own (to be turned into certificates
 * or reported; their pairs count as certified today):
 *   ssi_pairs.c NEAR_PLANAR 1e-12: a patch planar up to that fraction of its size is
 *     implicitised as the plane through three corners;
 *   clip.c PARAM_EPS 1e-10 (inside P's box), gap <= 10 tol (a sample on both surfaces), the
 *     densification steps (and a densification sample whose refinement slid beyond half the
 *     chord's parameter span is not used); a split point that slid beyond the samples' distance
 *     falls back to the inside sample; keep_piece's Dixon inversion at 100 tol;
 *   trace.c: branch ranks read in doubles, vertex sharpening;
 *   spline_pair.c: the entry/exit velocity 1e-9 (a consistency check; the count is proved),
 *     the marching's 1e-12 box slack;
 *   ssi_body.c, the faces' parameter boxes: 17 samples per edge (grown by the edges' deviation
 *     from their chords), an angle spanning a turn less 1e-6 (analytic faces) or 1e-9
 *     (revolutions, extrusions) taken as the whole turn, a point of a revolution with
 *     |S_u| <= 1e-9 |S_v| taken as on the axis (its angle left out), pcurves used for the box
 *     when they reach their edges' ends within the edge's tolerance. */

#endif
