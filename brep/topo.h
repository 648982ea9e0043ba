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

/* ---------------------------------------------------------------- topology ----------------- */

typedef struct {
    double p[3];
} cb_topo_vertex;

typedef struct {
    int curve;      /* index into body->curves */
    double t0, t1;  /* parameter range, t0 < t1 */
    int same_sense; /* curve direction agrees with v[0] -> v[1] */
    int v[2];       /* start and end vertex (equal for a closed edge) */
    double tol;     /* geometric tolerance of the edge (the file's uncertainty) */
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

/* Start and end point of a coedge's curve in traversal order. */
void cb_topo_coedge_ends(double start[3], double end[3], const cb_topo_body *b, int coedge);

/* Axis-aligned box of the vertices and of 17 points per edge curve. A face that bulges past
 * its boundary (a spherical cap) can leave it; the box of the face geometry itself needs the
 * trimmed face and is not computed here. */
void cb_topo_body_edge_box(cb_aabb *box, const cb_topo_body *b);

/* Counts of faces by surface type name, in order of first appearance: names[k] (static
 * strings) and counts[k] for k < return value (at most 8 types exist). */
int cb_topo_body_surface_types(const char *names[8], int counts[8], const cb_topo_body *b);

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

/* Checks the body, appending a sentence per problem to the report:
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
 * Not checked: outward orientation of the shells and pcurve consistency. Returns CB_OK when
 * the checks could run (the body is valid iff r->n == 0), CB_ERR_NOMEM otherwise. */
cb_status cb_topo_validate(cb_topo_report *r, cb_topo_body *b, double tol, int n_samples,
                           cb_error *err);

#endif
