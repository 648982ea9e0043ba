/* step.h — reading ISO 10303-21 (STEP AP203/AP214/AP242) B-rep models.
 *
 * What is read: every MANIFOLD_SOLID_BREP, BREP_WITH_VOIDS and SHELL_BASED_SURFACE_MODEL of
 * the file, with their CLOSED_SHELL / OPEN_SHELL / ORIENTED_CLOSED_SHELL, ADVANCED_FACE (or
 * FACE_SURFACE), FACE_BOUND / FACE_OUTER_BOUND, EDGE_LOOP, ORIENTED_EDGE, EDGE_CURVE and
 * VERTEX_POINT; surfaces PLANE, CYLINDRICAL_, CONICAL_, SPHERICAL_, TOROIDAL_SURFACE,
 * B-spline surfaces (simple or the complex rational form) with explicit knots
 * (B_SPLINE_SURFACE_WITH_KNOTS) or with the knots their form implies (UNIFORM_, QUASI_UNIFORM_,
 * BEZIER_SURFACE: ISO 10303-42's knot vectors), SURFACE_OF_REVOLUTION,
 * SURFACE_OF_LINEAR_EXTRUSION; curves LINE, CIRCLE, ELLIPSE, B-spline curves in the same forms,
 * PARABOLA and HYPERBOLA as exact rational quadratics (cb_nurbs_curve_parabola, _hyperbola)
 * over their TRIMMED_CURVE's trims or their edge's vertices, TRIMMED_CURVE as its basis curve
 * run in the trimmed curve's sense, SURFACE_CURVE / SEAM_CURVE / INTERSECTION_CURVE through
 * their 3D curve, and the PCURVEs these carry (2D lines, conics and B-splines), attached to the
 * coedge of the face on their surface. Unclamped B-spline knot vectors are clamped exactly by
 * knot insertion. Keywords and enumerations are read in any case (`Header;`); measures with
 * unit in their simple (4 parameters) and complex (MEASURE_WITH_UNIT part, 2) forms; in
 * strings, \S\c and a lone quote not followed by ',' or ')' are text. Geometry not listed
 * (OFFSET_SURFACE, RECTANGULAR_TRIMMED_SURFACE, COMPOSITE_CURVE, POLYLINE) is refused with
 * CB_ERR_UNSUPPORTED naming the entity and line, a horn torus as invalid. A
 * TOROIDAL_SURFACE whose major radius is below its minor one (a spindle torus, against the
 * schema's rule, as some systems write a screw head) is read as that torus, and so is a
 * DEGENERATE_TOROIDAL_SURFACE (the schema's spindle torus; its select_outer, which part the
 * faces use, is left to their bounds: the parametrisation is the torus's).
 * Entities the mapping does not reach are skipped. A VERTEX_LOOP bound (a pole or an apex
 * inside a face) is skipped too: it carries no edge. A face left with no loop (a whole sphere
 * or torus, written with a VERTEX_LOOP only or with no bound at all) gets the seams and poles
 * of its closed surface (cb_topo_close_faces), a torus face bounded by its two seams has
 * its loop put in the order the other routines read (ibid.), and a face whose loops wind
 * round a period of its surface without a seam edge (a cylinder band bounded by two circles,
 * a cone bounded by one circle round its apex) gets a seam (ibid.).
 *
 * Units: coordinates stay in the file's length unit; body->length_unit_mm gives its size
 * (SI_UNIT with any prefix, or CONVERSION_BASED_UNIT such as INCH). Angles are converted to
 * radians. The global UNCERTAINTY_MEASURE_WITH_UNIT becomes body->tol and every edge's tol
 * (1e-6 model units when the file gives none).
 *
 * Edge tolerances: files from real CAD systems carry edges farther from their faces than the
 * uncertainty they declare (linkrods.step: 4.1e-4 against 2e-5). As Open CASCADE's reader does,
 * once the pcurves are complete each edge's real deviation is measured: the largest distance,
 * over 65 samples of the edge curve (ends included; 17 where those stay within half the
 * edge's tolerance), to the surface of every face using it (cb_topo_projector, or the pcurve's
 * image where that is nearer), the gaps between its curve ends and its vertices, the distance
 * of its pcurves mapped through their surfaces to the edge (cb_topo_coedge_pcurve_error, 65
 * samples) and, at each loop joint where the gap between consecutive coedge ends exceeds both
 * edges' values, that gap for the edge whose end lies farther from the shared vertex. An edge whose
 * deviation times CB_STEP_EDGE_TOL_MARGIN exceeds its tolerance gets edge->tol = that product
 * (so points between samples are covered too), provided the deviation is at most the cap
 * max_edge_tol_rel times the diagonal of the body's edge box (cb_topo_body_edge_box); the
 * raised value never exceeds the cap. Beyond the cap the edge keeps the file's tolerance and
 * validation reports it. cb_topo_validate checks each edge against the larger of its tol
 * argument and edge->tol, so the edges of a body read here that lie within the cap pass its
 * edge checks at the file's own tolerance.
 *
 * Orientation: a closed shell of a solid written inside out (an outer shell enclosing a
 * negative volume, a void a positive one, by cb_topo_shell_volume) is turned round
 * (cb_topo_shell_reverse), as Open CASCADE's reader does.
 *
 * Assemblies: every solid is placed once per path up the assembly tree from a representation
 * holding it to a root (step_placements_for): each instance a solid of the body, moved by the
 * composed ITEM_DEFINED_TRANSFORMATIONs of (SHAPE_)REPRESENTATION_RELATIONSHIP_WITH_
 * TRANSFORMATION (rep_1 the child, transform_item_1 its placement, transform_item_2 the
 * placement in the parent; written parent first where the NEXT_ASSEMBLY_USAGE_OCCURRENCE of
 * its CONTEXT_DEPENDENT_SHAPE_REPRESENTATION says so, then inverted) and of MAPPED_ITEMs
 * (mapping_origin onto mapping_target in each shape representation holding the item).
 * Representations related without a transformation are one shape; equal placements of one
 * solid count once. Product names and the instance tree are not kept.
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

/* Default cap on measured edge tolerances, relative to the diagonal of the model's edge box.
 * 1e-4 of the model size is 10 um on a 100 mm part: about what precision machining holds, far
 * below any feature a Boolean has to resolve, yet above the 7.4e-5 of linkrods.step, a real
 * file from a real CAD system. Open CASCADE's reader bounds the tolerances it sets by a maximum
 * too (read.maxprecision, absolute: 1 model unit by default, which is far laxer). */
#define CB_STEP_MAX_EDGE_TOL_REL 1e-4

/* A raised edge tolerance is this factor times the deviation measured at the samples, so that
 * points between samples are covered too: on linkrods.step the largest deviation over 1025
 * samples of an edge exceeds that over the 65 by 1.1 % at most (over 33 samples it would miss
 * by up to 5.4 %). */
#define CB_STEP_EDGE_TOL_MARGIN 1.05

typedef struct {
    double max_edge_tol_rel; /* cap on edge tolerances relative to the edge-box diagonal
                                (CB_STEP_MAX_EDGE_TOL_REL); 0 leaves every edge at the file's
                                uncertainty */
} cb_step_options;

/* What the reader did to the tolerances. */
typedef struct {
    int edges_tol_raised; /* edges whose tol was raised to their measured deviation */
    int edges_over_cap;   /* edges deviating more than the cap (or whose pcurves still stray
                             beyond the raised tolerance after the rounds of step_tol.c):
                             left at the file's tol */
    double max_edge_tol;  /* largest edge tol of the body after reading */
    double edge_tol_cap;  /* the cap, model units */
} cb_step_stats;

/* Sets the defaults above. */
void cb_step_options_init(cb_step_options *opt);

/* Reads the file at path into a new body (*out, released with cb_topo_body_free). On failure
 * *out is NULL. The body is indexed (cb_topo_body_index) but not validated. Default options. */
cb_status cb_step_read(cb_topo_body **out, const char *path, cb_error *err);

/* The same from a buffer of len bytes; name is used in messages. */
cb_status cb_step_read_buffer(cb_topo_body **out, const char *data, size_t len, const char *name,
                              cb_error *err);

/* The two above with options (NULL: defaults) and, when stats is not NULL, what was done to
 * the edge tolerances (zeroed on failure). */
cb_status cb_step_read_opt(cb_topo_body **out, const char *path, const cb_step_options *opt,
                           cb_step_stats *stats, cb_error *err);
cb_status cb_step_read_buffer_opt(cb_topo_body **out, const char *data, size_t len,
                                  const char *name, const cb_step_options *opt,
                                  cb_step_stats *stats, cb_error *err);

#endif
