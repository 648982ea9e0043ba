/* topo.h — boundary representation: body -> solids -> shells -> faces -> loops -> coedges ->
 * edges -> vertices, with the geometry each level carries.
 *
 * Storage is index based: the body owns one array per entity kind and entities refer to each
 * other by index, so an edge shared by two faces is stored once and used by two coedges. The
 * children of a solid (shells), shell (faces), face (loops) and loop (coedges) are contiguous
 * ranges [first, first + count) of the child array. Geometry is held exactly as the source gave
 * it: analytic surfaces and conics keep their analytic kind, B-splines are rational B-splines
 * (brep/nurbs.h), surfaces of revolution and of linear extrusion keep their profile curve.
 *
 * Orientation conventions (those of ISO 10303-42):
 *   face    same_sense = 1: the face normal is the surface normal S_u x S_v, else its opposite;
 *   coedge  sense = 1: the coedge runs along its edge (from edge vertex v[0] to v[1]); the
 *           coedges of a loop are stored in traversal order, so coedge k ends where k + 1
 *           starts;
 *   edge    the edge runs from v[0] to v[1]; its curve is traversed over [t0, t1] (t0 < t1)
 *           from v[0] to v[1] when same_sense = 1, from v[1] to v[0] otherwise.
 * A closed, consistently oriented shell uses every edge in exactly two coedges of opposite
 * sense (a seam edge twice in the same face). */
#ifndef CB_TOPO_H
#define CB_TOPO_H

#include "brep/analytic.h"
#include "brep/bbox.h"
#include "brep/nurbs.h"

/* ---------------------------------------------------------------- curves ------------------- */

typedef enum { CB_CURVE_LINE, CB_CURVE_CIRCLE, CB_CURVE_ELLIPSE, CB_CURVE_NURBS } cb_curve_kind;

/* A 3D curve, or a 2D curve in a surface's parameter plane (z = 0) for pcurves:
 *   line     C(t) = o + t r1 z          (frame.z the unit direction, r1 > 0 the speed)
 *   circle   C(t) = o + r1 (cos t x + sin t y)
 *   ellipse  C(t) = o + r1 cos t x + r2 sin t y
 *   nurbs    the B-spline `nurbs` on its domain
 * Initialise with cb_topo_curve_init, release with cb_topo_curve_clear. */
typedef struct {
    cb_curve_kind kind;
    cb_frame frame;
    double r1, r2;
    cb_nurbs_curve_t nurbs;
} cb_topo_curve;

void cb_topo_curve_init(cb_topo_curve *c);
void cb_topo_curve_clear(cb_topo_curve *c);
const char *cb_curve_kind_name(cb_curve_kind kind);
/* d[0] = C(t), d[1] = C'(t), d[2] = C''(t). */
void cb_topo_curve_eval_derivs(double d[3][3], const cb_topo_curve *c, double t);
void cb_topo_curve_eval(double p[3], const cb_topo_curve *c, double t);
/* Parameter *t of the point of c nearest to p, and the distance to it. Lines are searched
 * over all t, conics over one period (result in [0, 2 pi)), B-splines over [a, b] (clamped to
 * their domain). Closed form for lines and circles; sampling followed by Newton steps for
 * ellipses and B-splines, so the distance returned is that of a curve point: never below the
 * true distance. */
double cb_topo_curve_project(double *t, const cb_topo_curve *c, const double p[3], double a,
                             double b);
/* Applies a rigid motion. */
void cb_topo_curve_transform(cb_topo_curve *c, const cb_xform *x);

/* ---------------------------------------------------------------- surfaces ----------------- */

typedef enum {
    CB_SURFACE_ANALYTIC, /* plane, cylinder, cone, sphere, torus (brep/analytic.h) */
    CB_SURFACE_NURBS,
    CB_SURFACE_REVOLUTION, /* S(u, v) = profile(v) turned by the angle u about the axis */
    CB_SURFACE_EXTRUSION   /* S(u, v) = profile(u) + v dir */
} cb_surface_kind;

/* revolution: axis through frame.o along frame.z; extrusion: dir (not normalised, as the file
 * gives it). Initialise with cb_topo_surface_init, release with cb_topo_surface_clear. */
typedef struct {
    cb_surface_kind kind;
    cb_analytic_surface analytic;
    cb_nurbs_surface_t nurbs;
    cb_topo_curve profile;
    cb_frame frame;
    double dir[3];
} cb_topo_surface;

void cb_topo_surface_init(cb_topo_surface *s);
void cb_topo_surface_clear(cb_topo_surface *s);
/* "plane", "cylinder", ..., "bspline", "revolution", "extrusion". */
const char *cb_topo_surface_type_name(const cb_topo_surface *s);
/* d[0] = S, d[1] = S_u, d[2] = S_v, d[3] = S_uu, d[4] = S_uv, d[5] = S_vv. */
void cb_topo_surface_eval_derivs(double d[6][3], const cb_topo_surface *s, double u, double v);
void cb_topo_surface_transform(cb_topo_surface *s, const cb_xform *x);

/* Distance from points to one surface (untrimmed: the whole analytic surface, the whole
 * parameter domain of a B-spline, the full turn of a revolution, the infinite extrusion).
 * Closed forms for plane, cylinder, cone, sphere and torus. Otherwise: nearest point of a
 * sample grid built once by _init (B-splines: 4 samples per knot span, at most 96 per
 * direction), refined by Newton steps on the squared distance, clamped to the domain. The
 * value returned is the distance to a point of the surface, so never below the true distance:
 * a point reported near is near. */
typedef struct {
    const cb_topo_surface *s;
    int nu, nv;
    double box[4]; /* parameter box sampled */
    double *grid;  /* nu * nv points, u outer */
} cb_topo_projector;

cb_status cb_topo_projector_init(cb_topo_projector *pr, const cb_topo_surface *s, cb_error *err);
void cb_topo_projector_clear(cb_topo_projector *pr);
double cb_topo_projector_distance(const cb_topo_projector *pr, const double p[3]);

/* Largest count cb_topo_projector_starts gives. */
#define CB_TOPO_MAX_STARTS 8

/* The (u, v) of the max (<= CB_TOPO_MAX_STARTS) grid samples nearest p, nearest first, as
 * starting points of a local search; returns how many there are. Samples at one point of
 * space (a collapsed row: a pole) give one start. Needs a sample grid (pr->grid not NULL). */
int cb_topo_projector_starts(double (*uv)[2], int max, const cb_topo_projector *pr,
                             const double p[3]);

/* ---------------------------------------------------------------- exact B-spline forms ----- */

/* The curve c over [t0, t1] as an exact rational B-spline: a line as degree 1 through C(t0) and
 * C(t1) (the B-spline parameter is t); a circle or ellipse (t1 - t0 at most a turn) as the
 * rational quadratic arc of cb_nurbs_curve_arc, or of cb_nurbs_curve_arc_exact with exact = 1
 * (the parameter equals t at the knots, cb_topo_curve_nurbs_param maps it); a B-spline as
 * itself, cut to [t0, t1] where that lies strictly inside its domain (its knots kept: the
 * parameter is t). Errors: CB_ERR_INVALID for an empty or non-finite range of a line or conic,
 * a conic range over a turn; CB_ERR_NOMEM. */
cb_status cb_topo_curve_to_nurbs(cb_nurbs_curve_t out, const cb_topo_curve *c, double t0,
                                 double t1, int exact, cb_error *err);
/* The parameter t of c at the parameter s of cb_topo_curve_to_nurbs(c, t0, t1, exact): s
 * itself, or for a conic cb_nurbs_arc_angle(t0, t1, exact, s). Strictly increasing, onto
 * [t0, t1]. */
double cb_topo_curve_nurbs_param(const cb_topo_curve *c, double t0, double t1, int exact,
                                 double s);

/* The surface s over range = {u0, u1, v0, v1} of its own parameters as an exact rational
 * B-spline, for an SSI or any routine that takes B-splines only:
 *   analytic    cb_analytic_to_nurbs (exact = 1: cb_analytic_to_nurbs_exact) over the range;
 *   B-spline    a copy of the whole surface (range not used);
 *   revolution  the profile over [v0, v1] (cb_topo_curve_to_nurbs) turned by [u0, u1] (at most
 *               a turn) about the axis (cb_nurbs_surface_revolve);
 *   extrusion   the profile over [u0, u1] swept along dir by [v0, v1] (degree 1 in v).
 * exact = 1 writes arcs that are whole quarter turns from whole quarter angles with weights
 * 1, 1, 2 (exact in binary, so exact tangencies stay exact); 0 with cos(pi / 4) rounded (the
 * symmetric form, as CAD systems write circles), whose rows at the two ends of a full turn are
 * bitwise the same. The image is s's over the range (to rounding of the control points); the
 * B-spline's parameters map to s's by cb_topo_surface_nurbs_param with the same exact.
 * Errors: CB_ERR_INVALID for ranges the conversions refuse (empty, unbounded where a line or
 * plane needs bounds, angles over a turn), naming the profile; CB_ERR_NOMEM. */
cb_status cb_topo_surface_to_nurbs(cb_nurbs_surface_t out, const cb_topo_surface *s,
                                   const double range[4], int exact, cb_error *err);
/* (u, v) of s at the parameters st of cb_topo_surface_to_nurbs(s, range, exact): closed form
 * per direction (cb_nurbs_arc_angle for the angles of arcs, the identity for lines and
 * B-spline profiles, which keep their parameter). Each direction is mapped by a continuous,
 * strictly increasing function of its own parameter onto the range, so the map is a bijection
 * of the B-spline's domain onto the range that keeps every curve's topology and the order of
 * points along it; S_nurbs(st) = s(uv). */
void cb_topo_surface_nurbs_param(double uv[2], const cb_topo_surface *s, const double range[4],
                                 int exact, const double st[2]);

/* ---------------------------------------------------------------- topology ----------------- */

typedef struct {
    double p[3];
} cb_topo_vertex;

typedef struct {
    int curve;      /* index into body->curves */
    double t0, t1;  /* parameter range, t0 < t1 */
    int same_sense; /* curve direction agrees with v[0] -> v[1] */
    int v[2];       /* start and end vertex (equal for a closed edge) */
    double tol;     /* geometric tolerance of the edge: the source's uncertainty, or the
                       edge's measured deviation from its faces where import raised it */
} cb_topo_edge;

typedef struct {
    int edge;
    int sense;  /* 1: along the edge */
    int pcurve; /* index into body->pcurves, or -1: the edge in the face's (u, v) */
    int loop;
} cb_topo_coedge;

typedef struct {
    int first, count; /* coedges */
    int outer;        /* the file marked it as the outer bound */
    int face;
} cb_topo_loop;

typedef struct {
    int surface; /* index into body->surfaces */
    int same_sense;
    int first, count; /* loops */
    int shell;
} cb_topo_face;

typedef struct {
    int first, count; /* faces */
    int closed;       /* declared closed (CLOSED_SHELL) */
    int solid;        /* -1 for a shell of a surface model */
} cb_topo_shell;

typedef struct {
    int first, count; /* shells; the first is the outer one, the others voids */
} cb_topo_solid;

/* Entity arrays grow with cb_topo_body_add_*; counts are n_*. */
typedef struct {
    cb_topo_vertex *vertices;
    cb_topo_edge *edges;
    cb_topo_coedge *coedges;
    cb_topo_loop *loops;
    cb_topo_face *faces;
    cb_topo_shell *shells;
    cb_topo_solid *solids;
    cb_topo_curve *curves;
    cb_topo_curve *pcurves;
    cb_topo_surface *surfaces;
    int n_vertices, n_edges, n_coedges, n_loops, n_faces, n_shells, n_solids, n_curves, n_pcurves,
        n_surfaces;
    int cap[10];
    double length_unit_mm; /* length of one model unit in millimetres (1 unless the source
                              used another unit; coordinates are kept in the source's unit) */
    double tol;            /* the source's global geometric tolerance, model units */
    /* Incidence, built by cb_topo_body_index: the coedges of edge e are
     * edge_coedges[edge_start[e] .. edge_start[e + 1]), the edges at vertex v are
     * vertex_edges[vertex_start[v] .. vertex_start[v + 1]) (a closed edge once). */
    int *edge_start, *edge_coedges, *vertex_start, *vertex_edges;
} cb_topo_body;

cb_topo_body *cb_topo_body_new(void);
void cb_topo_body_free(cb_topo_body *b);

/* Moves the whole body by the rigid motion x: vertices, edge curves and surfaces (pcurves,
 * in the surfaces' own parameters, stay valid). */
void cb_topo_body_transform(cb_topo_body *b, const cb_xform *x);

/* Appenders: each returns the new index (>= 0) or -1 when memory runs out, and zero-fills the
 * entity (curves and surfaces come initialised). They invalidate the incidence index and
 * pointers into the arrays. */
int cb_topo_body_add_vertex(cb_topo_body *b);
int cb_topo_body_add_edge(cb_topo_body *b);
int cb_topo_body_add_coedge(cb_topo_body *b);
int cb_topo_body_add_loop(cb_topo_body *b);
int cb_topo_body_add_face(cb_topo_body *b);
int cb_topo_body_add_shell(cb_topo_body *b);
int cb_topo_body_add_solid(cb_topo_body *b);
int cb_topo_body_add_curve(cb_topo_body *b);
int cb_topo_body_add_pcurve(cb_topo_body *b);
int cb_topo_body_add_surface(cb_topo_body *b);

/* Builds the edge -> coedge and vertex -> edge incidence used by the queries below; call it
 * after the last appender. Checks every index stored in the entities first and names the
 * first one out of range. */
cb_status cb_topo_body_index(cb_topo_body *b, cb_error *err);

/* ---------------------------------------------------------------- queries ------------------ */

/* Each writes at most max indices, distinct and increasing, to out and returns how many there
 * are in all (call with max = 0 to size the buffer), or -1 when out of memory. They need
 * cb_topo_body_index. */
int cb_topo_edge_faces(int *out, int max, const cb_topo_body *b, int edge);
int cb_topo_vertex_edges(int *out, int max, const cb_topo_body *b, int vertex);
/* Faces sharing an edge with the face, the face itself excluded. */
int cb_topo_face_neighbours(int *out, int max, const cb_topo_body *b, int face);

/* Length of edge e's curve over its range, by 16 chords (enough to tell a collapsed edge, a
 * pole or an apex, from a real one). */
double cb_topo_edge_length(const cb_topo_body *b, int e);

/* Start and end point of a coedge's curve in traversal order. */
void cb_topo_coedge_ends(double start[3], double end[3], const cb_topo_body *b, int coedge);

/* Axis-aligned box of the vertices and of 17 points per edge curve. A face that bulges past
 * its boundary (a spherical cap) can leave it; the box of the face geometry itself needs the
 * trimmed face and is not computed here. */
void cb_topo_body_edge_box(cb_aabb *box, const cb_topo_body *b);

/* Counts of faces by surface type name, in order of first appearance: names[k] (static
 * strings) and counts[k] for k < return value (at most 8 types exist). */
int cb_topo_body_surface_types(const char *names[8], int counts[8], const cb_topo_body *b);

/* Faces that cover their whole closed surface. CAD systems write a whole sphere or torus as
 * one face without edges: bounded by a VERTEX_LOOP only (Open CASCADE, and with the vertex on
 * a torus, other systems too) or by no bound at all. Colibri bounds every face by loops of
 * edges, as cb_prim_sphere lays out a sphere: this gives each face without a loop the
 * boundary of its surface's natural domain, so that validation, pcurves, tessellation, mass,
 * point classification, the SSI's face bounds, the Booleans (which split such a face like
 * any other) and the STEP writer need nothing of their own for it:
 *   - a surface closed in one direction whose two ends in the other collapse to points (the
 *     sphere and ellipsoid, analytic, as B-splines, revolved): one seam edge, the line of the
 *     surface at the start of the closed direction from pole to pole, two vertices (the
 *     poles), the loop [seam, seam reversed] (the pole lines are jumps of the loop);
 *   - a surface closed in both directions (torus): two seam edges, the lines at the start of
 *     each direction, through one vertex, the loop [along u, along v, along u reversed, along
 *     v reversed] when the face's normal is the surface's (counter-clockwise round the domain
 *     in (u, v)), [along v, along u, along v reversed, along u reversed] otherwise.
 * The seams are exact curves parameterised by the surface parameter they run along (conics for
 * the analytic surfaces, the boundary row of control points of a B-spline, the profile of a
 * revolution or its parallel), checked to lie within tol of the surface; each edge gets tol as
 * its tolerance. A face without a loop on any other surface (an open one: a plane, a cylinder)
 * is left as it is, and validation reports it.
 * A torus face bounded by its two seams alone, each used twice by its one loop (as Open
 * CASCADE writes a whole torus), gets the same boundary: its seams, vertex and coedges are
 * rewritten in place (their curves, ranges, order and pcurves; the seams must be used by
 * nothing else). The file's order of the four coedges, all at one vertex, chained clockwise in
 * (u, v) for a face whose normal is the surface's (its volume came out negative), and its
 * seams' parameter ranges and pcurves, lifted by a period, broke the Booleans' split of the
 * face where a cut crosses a seam.
 * The new coedges get their pcurves: the exact lines of the seam's two copies in (u, v), the
 * face to the left of each coedge when same_sense is 1 (a pcurve computed by inverting a
 * B-spline seam lands a rounding error off the domain's end, which puts the seam's two copies
 * less than a period apart). Appends entities (the incidence index must be rebuilt).
 * Bands (as Open CASCADE's ShapeFix_Face::FixMissingSeam fixes them): a face whose loops wind
 * round the period of its surface in one direction w without a seam edge (no edge used twice
 * by the face): two loops once each in opposite senses (a cylinder, cone, sphere zone or
 * torus band bounded by two circles), or one loop once with the surface collapsing to a point
 * on the face's side of it (a cone round its apex, a sphere cap; analytic and turned surfaces
 * only), every other loop winding round no period. The windings are found by following each
 * loop on the surface (16 inversions per edge, each next to the previous; a loop through a
 * pole or apex, where a step jumps by more than a quarter period, is not decided and its face
 * is left as it is). The face gets a seam: the line of its surface at the start of its domain
 * in w (where Open CASCADE's FixMissingSeam and brep/prim.h put seams, so the loop spans the
 * first period) from the first loop across the face to the second loop or the pole (a new
 * vertex there). A loop without a vertex on that line first gets one: the edge crossing the
 * line is split there (the crossing bisected on the edge curve), and every coedge of that
 * edge, in this face or its neighbour, becomes two. The loops become one loop [first loop from its vertex, seam, second
 * loop from its vertex (or the jump along the pole line), seam reversed], the seam running
 * across the face from the loop whose side the face lies on (to the left of it in (u, v) when
 * same_sense is 1); the seam's two coedges get the exact lines of its two copies a period
 * apart, the loop's other coedges lose their pcurves (computed afterwards, joined to the
 * seam's). The seams are exact: rulings of cylinders, cones and extrusions, meridians and
 * parallels of spheres, ellipsoids and tori, the profile and the parallels of revolutions, a
 * B-spline's boundary column; a face whose seam cannot be made so is left as it was.
 * Coedges are renumbered by the split and the join (the loops' ranges follow).
 * *closed counts the faces changed (may be NULL). A seam that cannot be made (not expected:
 * the curve found off its surface) leaves its face as it was. Errors: CB_ERR_NOMEM naming the
 * face. */
cb_status cb_topo_close_faces(cb_topo_body *b, double tol, int *closed, cb_error *err);

/* ---------------------------------------------------------------- parameter space ---------- */

/* Pcurve convention. The pcurve of a coedge is a curve in the (u, v) plane of its face's
 * surface (z = 0) parameterised like the edge's 3D curve: for t in the edge's [t0, t1],
 * S(pc(t)) = C(t) within the edge tolerance. The coedge runs over it as over the edge curve:
 * from t0 to t1 when coedge sense == edge same_sense, from t1 to t0 otherwise. A seam edge used
 * twice by one face has one pcurve per coedge, on the two sides of the seam (e.g. u = 0 and
 * u = 2 pi). Pcurves read from files may be parameterised otherwise (STEP allows it: rational
 * circles on planes); the routines below that use pcurves find the part of such a pcurve that
 * a coedge uses by projecting the edge's ends (cb_topo_coedge_pcurve_range). */

/* A surface prepared for point inversion: its periods, its parameter box and a start grid.
 *   period[i] > 0 when the surface closes on itself in direction i (u for i = 0): 2 pi for the
 *   angular parameters of the analytic surfaces and of revolutions, the domain length of a
 *   B-spline whose opposite boundary curves coincide within the tolerance given to _init.
 *   box = {u0, u1, v0, v1}: the parameter domain, -/+HUGE_VAL where unbounded (plane,
 *   cylinder v, ...); a periodic direction spans one period from box[2i].
 *   lift[i]: the shift of parameter i that leaves every point in place: the period, and also
 *   2 pi for the latitude of a sphere or ellipsoid (not a period of its domain, but files
 *   write pcurves at v and v - 2 pi alike).
 * Evaluation wraps a periodic parameter into the box first (B-splines are defined on their
 * domain only), so any real (u, v) may be given. */
typedef struct {
    const cb_topo_surface *s;
    double period[2];
    double lift[2];
    double box[4];
    cb_topo_projector pr;
} cb_topo_inverter;

cb_status cb_topo_inverter_init(cb_topo_inverter *inv, const cb_topo_surface *s, double tol,
                                cb_error *err);
void cb_topo_inverter_clear(cb_topo_inverter *inv);
/* d[0] = S, d[1] = S_u, ... as cb_topo_surface_eval_derivs, periodic parameters wrapped. */
void cb_topo_inverter_eval_derivs(double d[6][3], const cb_topo_inverter *inv, double u,
                                  double v);
void cb_topo_inverter_eval(double p[3], const cb_topo_inverter *inv, double u, double v);
/* Bit d (1 << d) set where the surface collapses in direction d at (u, v): |S_d| at most
 * 1e-9 of the other first derivative's length (a pole, an apex). */
int cb_topo_inverter_collapsed(const cb_topo_inverter *inv, double u, double v);
/* Points along a curve on the surface where the surface collapses (a pole, an apex:
 * cb_topo_inverter_collapsed) have a free parameter along the collapsed line, whatever
 * an inversion gave. Each maximal run of such points takes, in that parameter, the value of
 * the point before the run (the one after it for a run at the start), so that the curve does
 * not run along the collapsed line. uv: n points (u, v), stride bytes apart. */
void cb_topo_settle_poles(double *uv, size_t stride, int n, const cb_topo_inverter *inv);
/* (u, v) of the point of the surface nearest p; returns the distance |S(u, v) - p|.
 * guess NULL: global search (closed forms for plane, cylinder, cone, sphere, torus; start
 * grid or sampled profile otherwise), periodic parameters in [box[2i], box[2i] + period).
 * guess given: the nearest point is searched near it (a neighbouring sample of a curve being
 * projected), a parameter left undetermined by the geometry (u at a sphere pole or a cone
 * apex) keeps the guess's value, and periodic parameters are shifted by whole periods to the
 * lift nearest the guess; if that local search ends farther than the global one, the global
 * result is used (lifted likewise). Method: closed form or start, then Newton steps on
 * |S - p|^2 / 2 (Hessian where positive definite, Gauss-Newton otherwise), clamped to the
 * box in non-periodic directions. */
double cb_topo_inverter_invert(double uv[2], const cb_topo_inverter *inv, const double p[3],
                               const double guess[2]);

/* How far pcurve pc, taken at edge e's own parameters (the convention above), lies from the
 * edge's curve: the larger 3D distance at the edge's ends and middle, or HUGE_VAL where the
 * edge's range leaves a B-spline pcurve's domain. The first distance above tol is returned
 * without looking further (the callers only ask whether it is within tol; this runs for every
 * coedge in mass properties and tessellation). inv is prepared for the pcurve's surface. */
double cb_topo_pcurve_convention_gap(const cb_topo_curve *pc, const cb_topo_body *b, int e,
                                     const cb_topo_inverter *inv, double tol);

/* Pcurve parameters *s0, *s1 at which the pcurve of coedge c starts and ends, in the coedge's
 * traversal order. A pcurve following the convention above gives the edge's t0, t1 (swapped
 * when the coedge runs against the curve). Otherwise the 3D ends of the edge are inverted on
 * the surface and projected onto the pcurve in (u, v), trying the lifts by whole periods; a
 * closed edge takes its pcurve's whole domain (a full turn for a conic; a B-spline once round a
 * period of the surface, its ends one point of it) the way round the edge runs, and on a closed
 * pcurve the way round is the one whose middle lies on the edge: s1 may then lie outside a
 * B-spline's domain (evaluate with cb_topo_pcurve_eval). Returns the larger 3D
 * distance between an edge end and the surface point of the pcurve end found (the projection
 * is refined on that 3D distance, as the (u, v) metric may be far from the 3D one): a value above
 * the tolerance means the pcurve does not reach the edge's ends. inv is prepared for the
 * coedge's face surface. */
double cb_topo_coedge_pcurve_range(double *s0, double *s1, const cb_topo_body *b, int c,
                                   const cb_topo_inverter *inv, double tol);

/* A point of a pcurve at s; for a closed B-spline (equal ends), s outside the domain by more
 * than 1e-9 of it is first reduced by whole domain lengths (the part a coedge uses of a closed
 * pcurve may run through the domain's end:
 * cb_topo_coedge_pcurve_range then gives s1 beyond it). */
void cb_topo_pcurve_eval(double uv[3], const cb_topo_curve *pc, double s);

/* Largest distance from S(a) of the surface along the (u, v) segment a -> b (5 points): 0 for
 * equal points, tiny for two points on one collapsed line (a pole), so it tells whether a
 * joint in (u, v) closes on the surface. */
double cb_topo_inverter_spread(const cb_topo_inverter *inv, const double a[2],
                               const double b[2]);

/* Distance from p to edge e's curve over the edge's range [t0, t1] only (for a conic the arc,
 * not the whole circle). */
double cb_topo_edge_distance(const cb_topo_body *b, int e, const double p[3]);

/* Gives every coedge whose pcurve is -1 a pcurve by the convention above, appending it to
 * b->pcurves; coedges that have one keep it. tol > 0 is the fitting tolerance: the surface
 * point S(pc(t)) lies within tol of the foot point of C(t) on the surface at the sampled
 * parameters and at test points between them (so within tol plus the edge-surface gap of C(t)
 * itself).
 * Method, per coedge: samples of the edge inverted on the face surface in order, each
 * Newton search starting from the previous point, unwrapped across periods so the pcurve is
 * continuous. Exact curves where the image is one: a 2D line when (u, v) is affine in t
 * (lines on planes, rulings of cylinders and cones, circles along the parallels of surfaces
 * of revolution and the meridians of spheres and tori: found by testing), a 2D circle or
 * ellipse for a conic on a plane. Otherwise a cubic C1 Hermite B-spline through samples
 * (derivatives from the surface Jacobian, least squares; its minimum-norm solution at a pole),
 * bisected adaptively until the tolerance holds at three test points per piece; a piece the
 * bisection cannot shorten (1e-12 of the edge: the feet jump, as where an edge passes a concave
 * crease off the surface) is kept when it lies within the edge's own tolerance (the larger of
 * tol and the edge's) of the edge's curve at those points. Then per loop:
 * consecutive pcurves are shifted by whole periods so each starts where the previous one ends,
 * and the loop is lifted so its u (v) range is centred in the first period; the two coedges of
 * a seam edge in one face are put on its two sides (the one the loop reaches first stays, the
 * other moves by a period; with no neighbour to decide, the face lies to the left of the
 * coedge in (u, v) when the face's same_sense is 1, as ISO 10303-42 orients bounds). An edge
 * whose 3D curve collapses (length <= tol: a pole, a cone apex) becomes the 2D segment from
 * the previous coedge's end to the next one's start, along the pole line.
 * Needs the incidence index (call cb_topo_body_index first; it is rebuilt here when absent).
 * Errors: CB_ERR_NUMERIC naming the coedge when the fit does not converge (an edge through a
 * pole, where no continuous pcurve exists), CB_ERR_NOMEM. On error the coedges done keep their
 * new pcurves. */
cb_status cb_topo_compute_pcurves(cb_topo_body *b, double tol, cb_error *err);

/* How far coedge c's pcurve strays from its edge: the gap between the pcurve's ends and the
 * edge's ends (cb_topo_coedge_pcurve_range), or, when that is within the edge's tolerance
 * (the larger of tol and the edge's own), the largest distance from the surface point of the
 * pcurve to the edge at n_samples points. range receives the part of the pcurve the coedge
 * uses. inv is prepared for the coedge's face surface. */
double cb_topo_coedge_pcurve_error(double range[2], const cb_topo_body *b, int c,
                                   const cb_topo_inverter *inv, double tol, int n_samples);

/* Drops every pcurve that strays from its edge by more than the edge's tolerance (the larger
 * of tol and the edge's own; measured by cb_topo_coedge_pcurve_error at n_samples points) and
 * computes pcurves for the coedges without one (cb_topo_compute_pcurves, fitting tolerance
 * tol). Files carry pcurves that do not lie on their edges (linkrods.step: up to 0.05 off);
 * a kernel that trusted them would trim faces wrongly. *dropped counts the pcurves replaced.
 * Errors as cb_topo_compute_pcurves. */
cb_status cb_topo_repair_pcurves(cb_topo_body *b, double tol, int n_samples, int *dropped,
                                 cb_error *err);

/* Signed volume enclosed by shell k, from the divergence theorem: (1/3) the sum over its faces
 * of the integral of (x - c) . n dA over the trimmed face, n the face normal (same_sense
 * applied) and c the centre of the body's edge box. Each face is integrated over its domain in
 * (u, v): n_columns columns across the direction in which its loops do not wrap, each cut
 * by the loop polygons (the pcurves sampled, consecutive ones joined modulo the periods) into
 * inside intervals by crossing parity over every lift by a period, with Gauss points along the
 * intervals. A column crossed an odd number of times (a loop around a cylinder-like face that
 * ends at a pole) is closed at the pole side to the left of the loop. Positive for a closed
 * shell oriented outward, negative inward; the value approximates the volume to a few percent
 * with n_columns = 64. Needs a pcurve on every coedge of the shell (CB_ERR_INVALID naming the
 * coedge otherwise) and cb_topo_body_index; CB_ERR_UNSUPPORTED for a face whose loops wrap in
 * both directions of a doubly periodic surface. */
cb_status cb_topo_shell_volume(double *volume, const cb_topo_body *b, int shell, int n_columns,
                               double tol, cb_error *err);

/* Turns shell k inside out: every face's same_sense negated, the coedges of each of its loops
 * put in reverse order with their senses negated (so loops still run counter-clockwise about
 * the face's normal). Edges, curves, pcurves and surfaces are unchanged. Invalidates the
 * incidence index (call cb_topo_body_index again). */
void cb_topo_shell_reverse(cb_topo_body *b, int k);

/* ---------------------------------------------------------------- validation --------------- */

/* The problems found, as sentences naming the entities ("edge 12: used by 3 coedges"). */
typedef struct {
    char **items;
    int n, cap;
    int dropped;             /* problems beyond the 1000 kept */
    double max_edge_vertex;  /* largest distance from an edge curve end to its vertex */
    double max_loop_gap;     /* largest distance between consecutive coedge ends of a loop */
    double max_edge_surface; /* largest distance from an edge sample to a face surface */
} cb_topo_report;

void cb_topo_report_init(cb_topo_report *r);
void cb_topo_report_clear(cb_topo_report *r);

/* Checks the body, appending a sentence per problem to the report. Below, "within tol" for
 * anything belonging to an edge means within the edge's tolerance: the larger of tol and the
 * edge's own (edge->tol); a loop joint takes the larger of its two edges' tolerances.
 *   - every index in range (cb_topo_body_index);
 *   - closed shells: every edge used by exactly two coedges of the shell, of opposite sense;
 *     open shells: at most two, of opposite sense when two; an edge never used by two shells;
 *   - loops: consecutive coedges share their vertex, and the curve ends meet within tol;
 *   - edges: t0 < t1, and the curve ends lie within tol of the edge's vertices;
 *   - faces: at least one loop, no loop without coedges, loops of positive length (> tol);
 *   - edges on faces: n_samples points of every edge (its ends included) lie within tol of
 *     the surface of every face using it (cb_topo_projector).
 * tol is a distance in model units (a value <= 0 selects the body's own tolerance). The
 * largest deviations measured are recorded in the report whether or not they exceed tol.
 *   - pcurves: every pcurve, over the part its coedge uses (cb_topo_coedge_pcurve_range),
 *     maps through the surface onto its edge curve within tol at n_samples points;
 *   - loops whose coedges all carry pcurves are closed in (u, v): consecutive pcurve ends
 *     coincide modulo the surface periods, or lie on a line of the surface that collapses to
 *     one point (a pole);
 *   - faces whose coedges all carry pcurves, and whose loops passed the checks above, are not
 *     degenerate: the area their loops enclose on the surface (|S_u x S_v| integrated over the
 *     domain in (u, v) by columns, as cb_topo_shell_volume integrates) exceeds tol times the
 *     length of their loops, i.e. their mean width 2 area / length exceeds 2 tol ("face k:
 *     degenerate, its loops span no area" otherwise: a loop folded back on a line, which
 *     tessellation cannot mesh). Faces the columns cannot bound (loops around both periods of
 *     a torus, a loop around a periodic direction with no pole to close at) are not measured;
 *   - closed shells whose coedges all carry pcurves are oriented outward: their signed volume
 *     (cb_topo_shell_volume) is positive ("shell k: inward oriented" otherwise), negative for
 *     the voids of a solid, whose faces face into the cavity.
 * Returns CB_OK when
 * the checks could run (the body is valid iff r->n == 0), CB_ERR_NOMEM otherwise. */
cb_status cb_topo_validate(cb_topo_report *r, cb_topo_body *b, double tol, int n_samples,
                           cb_error *err);

#endif
