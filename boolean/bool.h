/* bool.h — the Boolean stage: broad phase over face boxes and point classification against a
 * closed B-rep.
 *
 * A Boolean of two closed bodies runs: broad phase (cb_bool_face_pairs: the face pairs whose
 * boxes overlap) -> intersection of those pairs (ssi/) -> imprinting of the curves as edges
 * splitting the faces -> classification of each face piece as inside, outside or on the other
 * solid (cb_bool_solid_classify at a point of the piece) -> selection and sewing. This header
 * holds the parts that do not depend on the intersection. */
#ifndef CB_BOOL_H
#define CB_BOOL_H

#include "brep/context.h"
#include "brep/face.h"
#include "ssi/ssi.h"

/* ---------------------------------------------------------------- BVH ---------------------- */

/* A bounding volume hierarchy over n boxes (item k is boxes[k]). Nodes split their items at
 * the median of the box centres along the longest axis of the centres' extent, down to at
 * most 4 items a leaf; the build is O(n log^2 n), deterministic, and a query costs O(log n +
 * output) for well-spread boxes. */
typedef struct {
    cb_aabb box;
    int left, right;  /* children, -1 in a leaf */
    int first, count; /* leaf: items order[first .. first + count) */
} cb_bool_bvh_node;

typedef struct {
    cb_bool_bvh_node *nodes;
    int n_nodes;
    int *order;
    cb_aabb *boxes; /* a copy of the input */
    int n_items;
} cb_bool_bvh;

/* Builds the tree (n >= 0; empty boxes are kept and never reported). CB_ERR_NOMEM,
 * CB_ERR_INVALID for a NaN coordinate (named). On failure t is left cleared. */
cb_status cb_bool_bvh_init(cb_bool_bvh *t, const cb_aabb *boxes, int n, cb_error *err);
void cb_bool_bvh_clear(cb_bool_bvh *t);

/* The items whose boxes overlap box within tol (cb_aabb_overlap), increasing: writes at most
 * max to out (the first found when there are more) and returns how many there are in all. */
int cb_bool_bvh_query_box(int *out, int max, const cb_bool_bvh *t, const cb_aabb *box,
                          double tol);

/* The items whose boxes, grown by tol, the segment o + s d, s in [s0, s1], meets, increasing;
 * as cb_bool_bvh_query_box. */
int cb_bool_bvh_query_ray(int *out, int max, const cb_bool_bvh *t, const double o[3],
                          const double d[3], double s0, double s1, double tol);

/* ---------------------------------------------------------------- broad phase -------------- */

/* Every pair (i, j), i < na, j < nb, with a[i] and b[j] overlapping within tol, sorted by i
 * then j: *pairs (malloc'd, free with free(); NULL when *n = 0) holds 2 *n ints. Method: a BVH
 * over b queried with each box of a. */
cb_status cb_bool_box_pairs(int **pairs, int *n, const cb_aabb *a, int na, const cb_aabb *b,
                            int nb, double tol, cb_error *err);

/* The boxes of the faces of body b (cb_face_box), boxes[k] for face k; prep_tol as for
 * cb_face_init. Errors of cb_face_init, prefixed with the face. */
cb_status cb_bool_face_boxes(cb_aabb *boxes, const cb_topo_body *b, double prep_tol,
                             cb_error *err);

/* The face pairs (face of A, face of B) whose boxes overlap within tol, as cb_bool_box_pairs;
 * faces prepared with each body's own tolerance (tol where the body gives none). */
cb_status cb_bool_face_pairs(int **pairs, int *n, const cb_topo_body *A, const cb_topo_body *B,
                             double tol, cb_error *err);

/* ---------------------------------------------------------------- point in solid ----------- */

typedef enum { CB_BOOL_OUT = 0, CB_BOOL_IN = 1, CB_BOOL_ON = 2 } cb_bool_where;

/* |cos| between a ray and a face normal below which a hit counts as grazing. */
#define CB_BOOL_GRAZE_COS 1e-2
/* Rays that must agree (with no valid ray against) for an answer; each disagreeing ray needs
 * two more in favour. */
#define CB_BOOL_AGREE 3
/* Rays cast at most before giving up. */
#define CB_BOOL_MAX_RAYS 24

/* A body prepared for point classification: its faces (cb_face) and a BVH over their boxes. */
typedef struct cb_bool_solid cb_bool_solid;

/* Prepares every face of b (indexed, a pcurve on every coedge) for classification with the
 * ON tolerance tol > 0 (model units). Faces are prepared with the body's tolerance (tol where
 * the body gives none). The body must outlive the handle. Errors of cb_face_init. */
cb_status cb_bool_solid_new(cb_bool_solid **out, const cb_topo_body *b, double tol, cb_error *err);
void cb_bool_solid_free(cb_bool_solid *s);

/* The prepared face k and the box of all faces. */
const cb_face *cb_bool_solid_face(const cb_bool_solid *s, int k);
void cb_bool_solid_box(cb_aabb *box, const cb_bool_solid *s);

/* Where p lies: ON when within tol of a face (cb_face_distance of the faces whose boxes are
 * within tol), else IN or OUT by the parity of the face crossings of rays from p. The rays'
 * directions come from a fixed sequence (the same for every point and run); a ray is rejected
 * when one of its hits grazes (|cos| < CB_BOOL_GRAZE_COS, or a tangent root) or lies within
 * tol of an edge. Rays are cast until one answer has CB_BOOL_AGREE more votes than twice the
 * other's; after CB_BOOL_MAX_RAYS rays without that, CB_ERR_NUMERIC with the vote counts.
 * Every shell of the body counts, voids included (a point in a void is OUT). The body must be
 * closed (not checked). Thread safe: several threads may classify with one handle. */
cb_status cb_bool_solid_classify(cb_bool_where *where, const cb_bool_solid *s, const double p[3],
                                 cb_error *err);

/* cb_bool_solid_classify against the faces first .. first + count - 1 only (one closed shell
 * of the body: which side of that shell p lies on, the other shells not counted). */
cb_status cb_bool_solid_classify_faces(cb_bool_where *where, const cb_bool_solid *s,
                                       const double p[3], int first, int count, cb_error *err);

/* The outward unit normal of the face of s nearest p (cb_face_distance), when one lies within
 * the handle's tolerance of p and has a normal there: 1; else 0 (n unset). Thread safe. */
int cb_bool_solid_normal_at(double n[3], const cb_bool_solid *s, const double p[3]);

/* One point against b: prepares, classifies and releases (use a cb_bool_solid for many). */
cb_status cb_bool_point_in_solid(cb_bool_where *where, const cb_topo_body *b, const double p[3],
                                 double tol, cb_error *err);

/* ---------------------------------------------------------------- cuts --------------------- */

/* Points of the result closer than this many tolerances are one vertex (see cb_bool_run). */
#define CB_BOOL_WELD 100
/* Points of a face's split closer than this many tolerances (in (u, v) scaled by the surface's
 * largest speeds) are one vertex of its arrangement; the loop polygon is refined to an eighth
 * of it where a cut comes within reach of it. Cut ends lie on the exact loops
 * (cb_bool_cuts_make), so it only has to absorb the polygon's deviation and rounding. */
#define CB_BOOL_SNAP 10

/* An intersection curve restricted to both its faces: the part of an SSI curve (cb_ssi_bodies)
 * inside the trimmed domains of face[0] of A and face[1] of B, as a polyline with its
 * parameters on both faces. uv[s] is in face[s]'s window: a periodic parameter lies in one
 * period centred on the face's loops (from the seam for a face that spans a whole period), so
 * the cut and the face's loops are in the same lift; a curve crossing a window's end is split
 * there into two cuts. closed: the last point repeats the first. */
typedef struct {
    int face[2];
    int curve; /* index of the SSI curve it comes from */
    int n;     /* points, >= 2 */
    double *xyz;
    double *uv[2];
    double *dir;    /* 3 n: unit tangent of the curve at each point, along the polyline */
    double *duv[2]; /* 2 n each: d(u, v)/ds on each face along dir (s the arc length) */
    int closed, tangential;
} cb_bool_cut;

typedef struct {
    int n, cap;
    cb_bool_cut *cut;
} cb_bool_cuts;

void cb_bool_cuts_init(cb_bool_cuts *c);
void cb_bool_cuts_clear(cb_bool_cuts *c);

/* The curve through a cut's points as a cubic B-spline whose parameter is the position
 * along the polyline (segment index + fraction): per segment the cubic Hermite arc with the
 * points' tangents, G1 at the points, so that the curve in 3D (side -1) and its images in
 * (u, v) on both faces (side 0, 1) meet each other to fourth order in the point spacing where
 * the linear polyline would only to second. out (initialised) is replaced. */
cb_status cb_bool_cut_curve(cb_topo_curve *out, const cb_bool_cut *c, int side, cb_error *err);

/* The point at position pos (segment index + fraction, clamped to [0, n - 1]) of the curve
 * cb_bool_cut_curve makes of cut c: x[3] in 3D (side -1), x[2] in the (u, v) of face side. */
void cb_bool_cut_point(double *x, const cb_bool_cut *c, int side, double pos);

/* Position *pos in [lo, hi] (segment index + fraction) of the point of cut c's polyline
 * nearest p, and its distance from p. The cut's curve (cb_bool_cut_curve) passes through the
 * polyline's points with the position as its parameter. */
double cb_bool_cut_project(double *pos, const cb_bool_cut *c, const double p[3], double lo,
                           double hi);

/* The cuts of every curve of r (SSI of A's faces against B's, face indices those of the
 * prepared solids A and B), appended to out. Inside means inside both trimmed faces by the
 * parity of their loops (cb_face_classify_uv) at the curve's points and, where a segment's
 * chord in (u, v) crosses a face's loops (cb_face_chord_crossings), between the crossings;
 * where a curve leaves a face its exit is found by bisection along the polyline segment
 * (points, parameters and positions interpolated linearly, so the exit lies on the face
 * boundary up to the polyline's chord error). An open piece no longer than tol (tol in model
 * units, > 0), or one made only of points added at loop crossings (none of the curve's own)
 * and no longer than CB_BOOL_SNAP tol, is dropped: a curve that only grazes a corner. Tangents:
 * the cross product of the face normals, or where the faces are tangent (their normals within
 * 1e-6 rad) the central difference of the points; in (u, v) the least squares solution of
 * J duv = dir (J the surface Jacobian), or the central difference where J is singular (a
 * pole). Cut ends within CB_BOOL_WELD tol of an earlier cut's end are moved onto it (curves
 * meeting at a node, computed from two face pairs; never both ends of one cut onto one
 * point), their parameters found again by inversion; on a face both cuts share, where the
 * moved end lay on the face's boundary (a boundary edge within CB_BOOL_SNAP tol, or a seam)
 * and the earlier one does not, both take the moved end's (u, v) there (not at a pole).
 * Errors: CB_ERR_INVALID for tol, CB_ERR_NOMEM (out is then cleared). */
cb_status cb_bool_cuts_make(cb_bool_cuts *out, const cb_ssi_result_struct *r,
                            const cb_bool_solid *A, const cb_bool_solid *B, double tol,
                            cb_error *err);

/* Restricts r, the result of cb_ssi_bodies(r, A, B, ...), to the trimmed faces: each curve is
 * replaced by its parts inside both faces (the cuts of cb_bool_cuts_make, exits refined onto
 * both surfaces, ends meeting within CB_BOOL_WELD tol made one point), the pieces of a curve
 * that were split only where it crosses a periodic window's end joined again (a loop around a
 * cylinder face stays one closed curve; its (u, v) jumps by the period at the seam), and
 * isolated points outside either face (cb_face_classify_uv, ON within tol counts as inside)
 * dropped. (u, v) are in the faces' windows (cb_bool_cut). Curve order follows r's. Failures,
 * coincident records and counters are left as they are. A and B must be indexed with a pcurve
 * on every coedge (the STEP reader's bodies are). Errors of cb_bool_solid_new, CB_ERR_INVALID
 * for tol, CB_ERR_NOMEM; r is then unchanged. */
cb_status cb_bool_ssi_trim(cb_ssi_result_struct *r, const cb_topo_body *A, const cb_topo_body *B,
                           double tol, cb_error *err);

/* ---------------------------------------------------------------- operations --------------- */

typedef enum { CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE } cb_bool_op;

/* "union", "intersection", "difference". */
const char *cb_bool_op_name(cb_bool_op op);

/* Default tolerance: this fraction of the diagonal of the box of both operands (the SSI's). */
#define CB_BOOL_REL_TOL 1e-6
/* Default chord of the intersection polylines (the sagitta of a segment), same fraction. */
#define CB_BOOL_REL_CHORD 1e-4

typedef struct {
    double tol;   /* model units; <= 0: CB_BOOL_REL_TOL times the operands' size */
    double chord; /* model units; <= 0: CB_BOOL_REL_CHORD times the operands' size */
} cb_bool_opts;

/* tol = chord = 0: the defaults. */
void cb_bool_opts_init(cb_bool_opts *o);

typedef struct {
    int curves, points; /* intersection curves and isolated points (SSI) */
    /* SSI outcomes (ssi/ssi.h): patch pairs certified, resolved within tolerance, and refused
     * (failure records; the operation fails when there is one); regions resolved within
     * tolerance (ssi/ssi_tol.h). */
    long ssi_certified, ssi_within_tolerance, ssi_refused, ssi_regions;
    int ssi_done; /* 1 once the intersection has run (the counts are then set) */
    int cuts;           /* curve pieces inside both faces (cb_bool_cuts_make) */
    int pieces[2];      /* face pieces of A and of B after splitting */
    int kept[2];        /* of which the operation keeps */
    int unmatched;      /* result edges not used by exactly two coedges */
    /* Seconds: the intersection (cb_ssi_bodies); the solids prepared for classification, the
     * cuts and the faces split; the result sewn. */
    double time_ssi, time_split, time_build;
} cb_bool_stats;

/* The union, intersection or difference A - B of two closed solids as a new body *out (free
 * with cb_topo_body_free). A and B: indexed (cb_topo_body_index), a pcurve on every coedge,
 * every shell a solid's and closed (each edge used by two coedges): CB_ERR_INVALID naming
 * what fails otherwise; both in the same length unit (CB_ERR_UNSUPPORTED otherwise).
 *
 * Method: the intersection curves of every face pair (cb_ssi_bodies; a refused pair, one
 * neither certified nor resolved within tolerance, makes the operation fail with
 * CB_ERR_UNSUPPORTED or the pair's status, naming it: nothing is guessed; pairs resolved
 * within tolerance are counted in stats), restricted to both faces (cb_bool_cuts_make); each face of A and B
 * split in its (u, v) domain along its cuts (the 2D arrangement of its loop polygon and cuts,
 * boolean/arrange.h); each region classified by a point inside it against the other solid
 * (cb_bool_solid_classify; when that point lies on the other solid, by points beside it, so a
 * contact line through the region does not decide) and kept as the operation selects (union: outside, intersection:
 * inside, difference: A's outside and B's inside, turned). Coincident faces (one surface, as the
 * SSI reports them): each is also split along the other's edges where they lie inside it
 * (boolean/imprint.c), and a region lying on the other solid keeps one copy, A's, where the
 * result's boundary runs: when the outward normals agree in union and intersection, when they
 * are opposite in A - B. Intersection curves running along a face's boundary or along such an
 * imprint are left out of that face's split. The kept regions become faces on
 * copies of their surfaces, their boundary pieces edges on copies of the original edge
 * curves, their cuts cubic Hermite B-spline edges through the intersection points with pcurves
 * of the same kind (cb_bool_cut_curve); pieces are sewn into shared edges where their end vertices (welded within
 * CB_BOOL_WELD tol) and curves agree (the nearest curve; two pieces of one curve between the
 * same ends sew with each other only), after a piece that would find no partner is split at
 * the ends of other such pieces lying on it (the faces along one curve need not be split at the
 * same points when coincident faces meet a third one); a region whose pieces all sew onto each
 * other at the same place (a sliver between two curves of different sources within the weld
 * distance) is no face; the other pcurves are computed (cb_topo_compute_pcurves).
 * The faces are grouped into shells connected by shared edges, each outward shell a solid
 * holding the inward shells (voids) inside it (boolean/op_shells.c); parts that touch only at
 * points are separate solids. The empty result has no solid.
 *
 * Not handled yet, reported and never guessed: a region touching the other solid where the
 * faces are not coincident (normals not within acos 0.9: CB_ERR_UNSUPPORTED), faces lying on one
 * surface only in part (CB_ERR_UNSUPPORTED), pieces that do not sew up (CB_ERR_NUMERIC with the
 * count). Isolated touching points do not split faces; operands touching along a curve or at
 * points give a union of solids that touch there, as the exact union does. ctx: threads for
 * the SSI's face pairs and for splitting the faces (the result does not depend on them),
 * progress (stage "boolean"), cancellation before each face pair of the intersection stage and
 * before each face split; may be NULL. stats may be NULL. */
cb_status cb_bool_run(cb_topo_body **out, cb_bool_stats *stats, cb_bool_op op,
                      const cb_topo_body *A, const cb_topo_body *B, const cb_bool_opts *opts,
                      cb_context *ctx, cb_error *err);

#endif
