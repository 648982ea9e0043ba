/* prim.h — primitive solids as B-rep bodies: box, sphere, cylinder, cone frustum, torus,
 * ellipsoid.
 *
 * Every builder returns a new body (free it with cb_topo_body_free) holding one solid with one
 * closed shell, oriented outward, with real edges and a pcurve on every coedge
 * (cb_topo_compute_pcurves), that passes cb_topo_validate with no problem. The shapes are laid
 * out as CAD systems write them to STEP: a periodic face is cut open along a seam edge used
 * twice by the face (once on each side of the seam in (u, v)); a pole or an apex is a vertex
 * where the seam ends, with no edge of its own (the face's loop jumps along the pole line
 * there, as the pcurves of cb_topo_compute_pcurves do).
 *
 * Placement: a frame f (cb_frame_make; NULL: the world frame at the origin) gives the local
 * coordinates (x', y', z') in which each shape is described below; the seam lies in the
 * half-plane y' = 0, x' > 0.
 *
 * as_nurbs = 0 keeps every face on its analytic surface (brep/analytic.h; planes, cylinders,
 * cones, spheres, tori, ellipsoids in the frames described); 1 writes every face as an exact
 * rational B-spline (cb_analytic_to_nurbs) over the face's own parameter range. Edge curves
 * are lines, circles and ellipses either way.
 *
 * tol is the body's geometric tolerance in model units: stored as the body's and every edge's
 * tolerance, and the fitting tolerance of the computed pcurves; tol <= 0 selects
 * CB_PRIM_REL_TOL times the size of the shape (its largest extent).
 *
 * Errors: CB_ERR_INVALID with a message naming the bad size (non-finite, <= 0, the torus'
 * r >= R, ...) or frame (non-finite); CB_ERR_NOMEM; CB_ERR_NUMERIC if the pcurves cannot be
 * fitted (not expected for valid sizes). *out is NULL on failure. */
#ifndef CB_PRIM_H
#define CB_PRIM_H

#include "brep/topo.h"

/* Default tolerance relative to the size of the shape. */
#define CB_PRIM_REL_TOL 1e-9

/* Box lo <= (x', y', z') <= hi (lo[i] < hi[i]): 6 planar faces with outward normals, 12 line
 * edges, 8 vertices. */
cb_status cb_prim_box(cb_topo_body **out, const cb_frame *f, const double lo[3], const double hi[3],
                      int as_nurbs, double tol, cb_error *err);

/* Sphere of the given radius about the frame origin: 1 face, 1 edge (the seam, the meridian
 * from the south pole (0, 0, -r) to the north pole (0, 0, r) through (r, 0, 0)), 2 vertices
 * (the poles). */
cb_status cb_prim_sphere(cb_topo_body **out, const cb_frame *f, double radius, int as_nurbs,
                         double tol, cb_error *err);

/* Ellipsoid x'^2/a^2 + y'^2/b^2 + z'^2/c^2 <= 1: laid out as the sphere, the seam a
 * half-ellipse: 1 face, 1 edge, 2 vertices. */
cb_status cb_prim_ellipsoid(cb_topo_body **out, const cb_frame *f, double a, double b, double c,
                            int as_nurbs, double tol, cb_error *err);

/* Cylinder of the given radius on 0 <= z' <= height: 3 faces (side, bottom and top discs),
 * 3 edges (two circles, the seam line), 2 vertices (the seam's ends). */
cb_status cb_prim_cylinder(cb_topo_body **out, const cb_frame *f, double radius, double height,
                           int as_nurbs, double tol, cb_error *err);

/* Cone frustum on 0 <= z' <= height, radius r0 at z' = 0 and r1 at z' = height (r0 != r1,
 * both >= 0, at most one of them 0). Both > 0: 3 faces, 3 edges, 2 vertices as the cylinder.
 * One radius 0, a true cone: 2 faces (side and one disc), 2 edges (the circle and the seam
 * from the circle to the apex), 2 vertices (the apex is one). The conical surface is placed
 * with its origin on the smaller end and its axis towards the larger (cone radii grow with
 * v): its frame is f when r0 < r1, else f turned upside down about x'. */
cb_status cb_prim_cone(cb_topo_body **out, const cb_frame *f, double r0, double r1, double height,
                       int as_nurbs, double tol, cb_error *err);

/* Ring torus about the z' axis, major radius R > minor radius r > 0. Cut in two faces, the
 * halves y' >= 0 (u in [0, pi]) and y' <= 0 (u in [pi, 2 pi]), so that no face wraps around
 * both periods: 2 faces, 4 edges (the meridian circles at u = 0 and u = pi, the two halves of
 * the outer equator, each a seam of its face), 2 vertices ((R + r, 0, 0) and (-R - r, 0, 0)). */
cb_status cb_prim_torus(cb_topo_body **out, const cb_frame *f, double major_radius,
                        double minor_radius, int as_nurbs, double tol, cb_error *err);

#endif
