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

#include "brep/face.h"

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

/* One point against b: prepares, classifies and releases (use a cb_bool_solid for many). */
cb_status cb_bool_point_in_solid(cb_bool_where *where, const cb_topo_body *b, const double p[3],
                                 double tol, cb_error *err);

#endif
