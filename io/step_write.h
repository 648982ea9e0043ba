/* step_write.h — writing a B-rep body as a STEP AP214 file (ISO 10303-21).
 *
 * Geometry is written exactly as the body holds it: planes, cylinders, cones, spheres and tori
 * as their STEP elementary surfaces, B-splines as B_SPLINE_SURFACE_WITH_KNOTS (the complex
 * rational form when a weight differs from 1), surfaces of revolution and extrusion with their
 * profiles; lines, circles, ellipses and B-spline curves likewise. STEP has no ellipsoid: an
 * ellipsoid face is written as its exact rational B-spline (cb_analytic_to_nurbs). Reals are
 * printed with 17 significant digits, so a reader gets back the same doubles.
 *
 * The file carries the AP214 (AUTOMOTIVE_DESIGN) schema, one product with its definition and
 * shape, the body's length unit (SI millimetre, centimetre or metre, else a conversion-based
 * unit in millimetres), radians, and the body's tolerance as the uncertainty. Solids become
 * MANIFOLD_SOLID_BREP (BREP_WITH_VOIDS when they have voids) in an
 * ADVANCED_BREP_SHAPE_REPRESENTATION; a body of shells without solids becomes a
 * SHELL_BASED_SURFACE_MODEL in a MANIFOLD_SURFACE_SHAPE_REPRESENTATION. Pcurves are written
 * for seam edges only (an edge used twice by one face: a SEAM_CURVE with the pcurves of its two
 * uses, lines or B-splines in the (u, v) of the face's surface, not on an ellipsoid): which
 * side of the seam each use lies on is what a reader cannot always tell without them. */
#ifndef CB_IO_STEP_WRITE_H
#define CB_IO_STEP_WRITE_H

#include "brep/topo.h"

/* Writes b to path; `name` becomes the product name (NULL: "colibri"). A body with both solids
 * and shells outside them, a non-finite coordinate, or an unknown entity kind is refused
 * with CB_ERR_UNSUPPORTED / CB_ERR_INVALID before anything is written; a write error gives
 * CB_ERR_IO and removes the partial file. */
cb_status cb_step_write(const cb_topo_body *b, const char *path, const char *name,
                        cb_error *err);

#endif
