/* step.h — reading ISO 10303-21 (STEP AP203/AP214/AP242) B-rep models.
 *
 * What is read: every MANIFOLD_SOLID_BREP, BREP_WITH_VOIDS and SHELL_BASED_SURFACE_MODEL of
 * the file, with their CLOSED_SHELL / OPEN_SHELL / ORIENTED_CLOSED_SHELL, ADVANCED_FACE (or
 * FACE_SURFACE), FACE_BOUND / FACE_OUTER_BOUND, EDGE_LOOP, ORIENTED_EDGE, EDGE_CURVE and
 * VERTEX_POINT; surfaces PLANE, CYLINDRICAL_, CONICAL_, SPHERICAL_, TOROIDAL_SURFACE,
 * B_SPLINE_SURFACE_WITH_KNOTS (simple or the complex rational form), SURFACE_OF_REVOLUTION,
 * SURFACE_OF_LINEAR_EXTRUSION; curves LINE, CIRCLE, ELLIPSE, B_SPLINE_CURVE_WITH_KNOTS (simple
 * or rational), SURFACE_CURVE / SEAM_CURVE / INTERSECTION_CURVE through their 3D curve, and the
 * PCURVEs these carry (2D lines, conics and B-splines), attached to the coedge of the face on
 * their surface. Unclamped B-spline knot vectors are clamped exactly by knot insertion.
 * Entities the mapping does not reach are skipped. A VERTEX_LOOP bound (a cone apex) is
 * skipped too: it carries no edge.
 *
 * Units: coordinates stay in the file's length unit; body->length_unit_mm gives its size
 * (SI_UNIT with any prefix, or CONVERSION_BASED_UNIT such as INCH). Angles are converted to
 * radians. The global UNCERTAINTY_MEASURE_WITH_UNIT becomes body->tol and every edge's tol.
 *
 * Assemblies: a solid held by a representation that is linked up a tree of
 * (SHAPE_)REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION to a root is moved by the composed
 * ITEM_DEFINED_TRANSFORMATIONs (rep_1 the child, transform_item_1 its placement, transform_item_2
 * the placement in the parent). Each solid is read once, in the placement of its first chain;
 * instancing one part several times (MAPPED_ITEM, repeated relationships) is not expanded.
 *
 * Errors: CB_ERR_IO when the file cannot be read; CB_ERR_PARSE for malformed syntax or
 * parameters of the wrong kind or count; CB_ERR_INVALID for inconsistent content (dangling or
 * cyclic references, bad knot vectors, zero directions, absurd numbers); CB_ERR_UNSUPPORTED
 * for geometry the reader does not handle. The message reads
 *   "file:line: #id ENTITY: what is wrong"
 * e.g. "trj5.stp:1843: #1207 B_SPLINE_SURFACE_WITH_KNOTS: u: 12 knots given, 13 expected (...)".
 * Memory is a fixed multiple of the file size; reference chains are followed with cycle
 * detection and a depth limit, so no input makes the reader loop. */
#ifndef CB_IO_STEP_H
#define CB_IO_STEP_H

#include <stddef.h>

#include "brep/topo.h"

/* Reads the file at path into a new body (*out, released with cb_topo_body_free). On failure
 * *out is NULL. The body is indexed (cb_topo_body_index) but not validated. */
cb_status cb_step_read(cb_topo_body **out, const char *path, cb_error *err);

/* The same from a buffer of len bytes; name is used in messages. */
cb_status cb_step_read_buffer(cb_topo_body **out, const char *data, size_t len, const char *name,
                              cb_error *err);

#endif
