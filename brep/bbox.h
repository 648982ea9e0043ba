/* bbox.h — axis-aligned and oriented bounding boxes of point sets and NURBS control nets.
 *
 * A rational curve or surface with positive weights lies in the convex hull of its Euclidean
 * control points cw / w, so a box of those points bounds the geometry. The SSI driver culls
 * patch pairs whose boxes are separated (Yang, Jia, Yan, "Topology guaranteed B-spline
 * surface/surface intersection", ACM TOG 2023, sec. 4.1); the oriented box is the tight one.
 *
 * Points are read as point i = pts + i * stride (stride counted in doubles, >= 3); coordinates
 * must be finite. Tolerances are explicit arguments and are distances (>= 0). */
#ifndef CB_BBOX_H
#define CB_BBOX_H

#include <stddef.h>

#include "brep/nurbs.h"

/* ---------------------------------------------------------------- axis-aligned -------------- */

/* Empty when lo[k] > hi[k] for some k (the box of no points has lo = +inf, hi = -inf). */
typedef struct {
    double lo[3], hi[3];
} cb_aabb;

/* Exact bounds: lo and hi are the coordinate minima and maxima, no rounding. */
void cb_aabb_of_points(cb_aabb *b, const double *pts, size_t n, size_t stride);

/* Product of the side lengths; 0 for an empty box. */
double cb_aabb_volume(const cb_aabb *b);

/* 1 when the boxes are nonempty and along every axis their intervals are at most tol apart
 * (so 0 proves a gap > tol along some axis), else 0. */
int cb_aabb_overlap(const cb_aabb *a, const cb_aabb *b, double tol);

/* ---------------------------------------------------------------- oriented ----------------- */

/* The box { center + sum_k t_k axis[k] : |t_k| <= half[k] }. The rows of axis are orthonormal
 * and right-handed (axis[2] = axis[0] x axis[1]) to round-off. Empty when some half[k] < 0
 * (the box of no points has half = -1). */
typedef struct {
    double center[3];
    double axis[3][3];
    double half[3];
} cb_obb;

/* A small-volume oriented box holding every point.
 *
 * Method: trial axes — the world axes, the principal axes of the covariance (cyclic Jacobi),
 * a frame from the farthest pair of extreme points and the point farthest from their line,
 * and 16 directions spread over a hemisphere in the principal frame — each give the box with
 * that axis and the least rectangle across it (exact: one side of a minimum-area rectangle
 * lies on the convex hull of the projected points). The 3 best are refined by coordinate
 * descent, each step such an exact rotation about one box axis. The world frame is a
 * candidate to the end, so the result is never larger than the AABB (up to the round-off pad
 * below). Coincident, collinear and coplanar sets give finite boxes with zero extents where
 * the set has none (up to the pad); a flat set gets its least rectangle in its plane.
 *
 * Sets of more than 256 points are searched through their extreme points in 128 directions
 * (a kernel: nearly the same width as the set in every direction), to which the points
 * extreme on the chosen box are added until it has no misses (at most 4 rounds); the final
 * extents are always taken over every point.
 *
 * Containment is exact: every input point p satisfies cb_obb_contains(b, p, 0). The half
 * extents are measured with the arithmetic of cb_obb_contains and then padded by 32 ulps of
 * the largest coordinate magnitude, so points that differ from the input by a few ulps (for
 * instance recomputed as wx / w) are contained too.
 *
 * No allocation (about 25 KB of stack). Time: a few passes over the set (128 dot products
 * a point above 256 points) and about 60 convex hulls of at most 280 projected points —
 * some 20 us for a bicubic Bezier net, 4 ms for 20000 points. */
void cb_obb_of_points(cb_obb *b, const double *pts, size_t n, size_t stride);

/* 8 half[0] half[1] half[2]; 0 for an empty box. */
double cb_obb_volume(const cb_obb *b);

/* 1 when |(p - center) . axis[k]| <= half[k] + tol for k = 0, 1, 2 (the box grown by tol in
 * each axis direction), else 0; 0 for an empty box. */
int cb_obb_contains(const cb_obb *b, const double p[3], double tol);

/* 1 only when the boxes are proven to be more than tol apart: by the separating axis theorem
 * some axis among the 3 + 3 face normals and the 9 edge cross products shows a gap
 * > tol + g, where g (32 ulps of the magnitudes of centers and extents) covers the round-off
 * of the test itself. Cross products of edges parallel to working precision (length
 * <= DBL_EPSILON) are skipped, which is conservative; for exactly parallel edges the face
 * normals already decide. 1 when either box is empty. A 0 only says that no tested axis
 * shows a gap > tol + g: the boxes may still be farther apart than tol (corner to corner). */
int cb_obb_separated(const cb_obb *a, const cb_obb *b, double tol);

/* Corner k is center + sum_i s_i half[i] axis[i], s_i = +1 if bit i of k is set, else -1. */
void cb_obb_corners(double c[8][3], const cb_obb *b);

/* ---------------------------------------------------------------- control nets ------------- */

/* Boxes of the Euclidean control points cw / w (no copy is made). The AABB is exact for those
 * points; evaluated curve or surface points can leave it by their own evaluation round-off. */
void cb_nurbs_curve_aabb(cb_aabb *b, const cb_nurbs_curve_t c);
void cb_nurbs_curve_obb(cb_obb *b, const cb_nurbs_curve_t c);
void cb_nurbs_surface_aabb(cb_aabb *b, const cb_nurbs_surface_t s);
void cb_nurbs_surface_obb(cb_obb *b, const cb_nurbs_surface_t s);

#endif
