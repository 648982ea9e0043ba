/* face.h — queries on one trimmed face of a B-rep body: where a parameter point lies with
 * respect to the face's loops, a box holding the face, the intersections of a ray with the
 * face, and the distance from a point to the face.
 *
 * A face is prepared once (cb_face_init: the surface inverter, the loops sampled in (u, v),
 * boxes of the edges and of the surface), then queried from any number of threads: the
 * queries only read the prepared face. The body must outlive the prepared face and must not
 * change meanwhile. Every coedge of the face needs a pcurve (cb_topo_compute_pcurves; the STEP
 * reader gives every coedge one).
 *
 * The trimmed domain. The loops' pcurves are sampled into polygons in (u, v), each pcurve
 * lifted by whole periods to continue the previous one (brep/topo.h). A point is inside when
 * a ray from it across the loops crosses them an odd number of times (every lift by a period
 * counted), a loop around a periodic direction that ends at a pole (a spherical cap) being
 * closed along the pole line on the side the face lies on. Near the point the polygon is
 * replaced by the exact pcurve: a polygon segment whose deviation bound reaches the point is
 * bisected on the pcurve until it does not, so the answer is that of the exact loops, not of a
 * coarse polygon. (The bound is 1.5 times the deviation measured at 3 inner points, and for
 * halves twice their midpoint's, at least a quarter of the parent's: a heuristic, not a
 * proof, for pcurves that wiggle between samples.) The boundary test is in 3D: S(u, v) is ON
 * when it lies within tol + off of an edge of the face (off: how far the image of the edge's
 * pcurve strays from the edge, measured by cb_face_init), seams (an edge used twice by the
 * face) and collapsed edges (poles, apexes, length <= the face's tolerance) excepted. Faces
 * whose loops wrap around both periods of a doubly periodic surface are not supported. */
#ifndef CB_FACE_H
#define CB_FACE_H

#include "brep/topo.h"

typedef enum { CB_FACE_OUT = 0, CB_FACE_IN = 1, CB_FACE_ON = 2 } cb_face_where;

/* One polygon segment of a loop in (u, v), from p to q: the image of pcurve parameters
 * [s0, s1] of coedge `coedge` moved by `shift` (whole periods), within `dev` of the chord in
 * (u, v); coedge -1 for a straight join (along a pole line, or closing a loop by a period). */
typedef struct {
    double p[2], q[2];
    double s0, s1;
    double shift[2];
    double dev;
    int coedge;
} cb_face_seg;

/* An edge of the face: its index, whether it can hold boundary points (not a seam of the
 * face, not collapsed), a box holding its curve, n + 1 samples of the curve at equal
 * parameter steps (every curve point within gap of one of them), and off: how far the image
 * of its pcurve in this face strays from it (cb_topo_coedge_pcurve_error at 17 points; files
 * carry edges off their faces). */
typedef struct {
    int edge;
    int boundary;
    cb_aabb box;
    double (*samples)[3];
    int n;
    double gap;
    double off;
} cb_face_edge;

/* A cell of the sampled surface over the face's (u, v) box (surfaces without a closed-form
 * ray intersection): the parameter rectangle and the box of 3 x 3 samples grown by twice
 * their bilinear deviation and the face's tolerance (meant to hold the surface over it). */
typedef struct {
    double uv[4];
    cb_aabb box;
} cb_face_cell;

typedef struct {
    const cb_topo_body *b;
    int face;
    double tol; /* the preparation tolerance */
    cb_topo_inverter inv;
    cb_face_seg *segs;
    int n_segs;
    cb_face_edge *edges;
    int n_edges;
    /* Crossing rays run along b = 1 - a in columns a = const; the loops lie in
     * uv_box = {u0, u1, v0, v1}; a column crossed an odd number of times is closed at
     * pole_b (above the point when pole_up). */
    int a;
    double uv_box[4];
    double pole_b;
    int pole_up;
    cb_aabb box; /* holds every point of the trimmed face */
    cb_face_cell *cells;
    int n_cells;
    double size; /* diagonal of box */
} cb_face;

/* Prepares face `face` of b (indexed, cb_topo_body_index). tol > 0 is the geometric tolerance
 * (model units) used to tell closed loop joints and collapsed edges (the body's tolerance is a
 * good choice); the queries take their own tolerances. Errors: CB_ERR_INVALID (face index out
 * of range, a coedge without pcurve: named), CB_ERR_UNSUPPORTED (loops around both periods),
 * CB_ERR_NOMEM. On failure f is left cleared. */
cb_status cb_face_init(cb_face *f, const cb_topo_body *b, int face, double tol, cb_error *err);
void cb_face_clear(cb_face *f);

/* The fractions in (0, 1) at which the straight chord a -> b in (u, v) crosses the face's
 * loops, every lift of a periodic parameter counted, appended to *t[*n ..] (grown by realloc;
 * *cap its size). Near the chord the loop polygon is replaced by the exact pcurves, as in the
 * classification (a segment whose deviation band reaches the chord is bisected on its
 * pcurve). A chord touching a loop where two segments meet may count that crossing twice.
 * CB_ERR_NOMEM when out of memory (no message: the caller names where). */
cb_status cb_face_chord_crossings(double **t, int *n, int *cap, const cb_face *f,
                                  const double a[2], const double b[2]);

/* Where (u, v) lies: CB_FACE_ON when S(u, v) is within tol (a 3D distance, > 0) plus the
 * edge's off of a boundary edge, else IN or OUT of the trimmed domain. Any lift of a periodic
 * parameter may be given. */
cb_face_where cb_face_classify_uv(const cb_face *f, double u, double v, double tol);

/* Distance from p to the nearest boundary edge of the face (seams and collapsed edges not
 * counted); the distance to a point of an edge, so never below the true one. */
double cb_face_boundary_distance(const cb_face *f, const double p[3]);

/* The conservative axis-aligned box computed by cb_face_init: every point of the trimmed
 * face lies in it. Method: the (u, v) box of the loops (closed to the pole where a loop around
 * a period ends there); analytic surfaces as exact rational B-splines over that box
 * (cb_analytic_to_nurbs), whose control points hold the surface; B-splines split to the
 * sub-patch over the box, same argument; surfaces of revolution and extrusion from balls
 * holding the profile over its range, turned about the axis or swept along the direction. */
void cb_face_box(cb_aabb *box, const cb_face *f);

/* A box holding surface s over the parameter rectangle uv = {u0, u1, v0, v1} (finite), by the
 * method above; angular ranges longer than a period are cut to one period; a sphere's or
 * ellipsoid's latitude range reaching past a pole gives the box of the whole surface.
 * Errors: CB_ERR_INVALID for a non-finite rectangle, CB_ERR_NOMEM. */
cb_status cb_face_surface_box(cb_aabb *box, const cb_topo_surface *s, const double uv[4],
                              cb_error *err);

/* ---------------------------------------------------------------- rays --------------------- */

typedef enum {
    CB_FACE_HIT_CROSS = 0, /* transversal, inside the face */
    CB_FACE_HIT_GRAZE = 1, /* inside the face but |cos| of the angle between the ray and the
                              normal below the caller's threshold, or the normal undefined */
    CB_FACE_HIT_EDGE = 2   /* within tol of a boundary edge (cb_face_classify_uv ON) */
} cb_face_hit_kind;

typedef struct {
    double t;        /* point o + t d */
    double u, v;     /* its parameters */
    double cos;      /* d . n / (|d| |n|), n the face normal (same_sense applied); 0 if undefined */
    cb_face_hit_kind kind;
} cb_face_hit;

/* All intersections of the ray o + t d, t in [t0, t1], with the trimmed face, by increasing t;
 * points outside the trimmed domain are dropped. Writes at most max hits and returns how many
 * there are in all. tol: the ON distance to edges; graze: the |cos| below which a hit is
 * GRAZE (e.g. 1e-3). A ray tangent to the surface gives its touching point as GRAZE when it is
 * found. Method: closed forms for planes, cylinders, cones, spheres, ellipsoids (quadratic in
 * t) and tori (quartic, roots isolated between the roots of its derivatives and polished by
 * Newton steps); other surfaces: Newton steps on S(u, v) = o + t d from the centre of each
 * cell of cb_face_init (16 to 64 per direction) whose box the ray meets, roots found twice
 * merged (the cell boxes are boxes of 3 x 3 samples inflated by twice the measured bilinear
 * deviation: a heuristic bound, not a proof; a root whose Newton iteration does not converge
 * from its cell's centre is missed). */
int cb_face_ray(cb_face_hit *hits, int max, const cb_face *f, const double o[3], const double d[3],
                double t0, double t1, double tol, double graze);

/* Distance from p to the trimmed face and the (u, v) of the face point reached (uv may be
 * NULL). The nearest point is searched among the local minima of the distance to the surface
 * from up to CB_TOPO_MAX_STARTS starts (kept when inside the trimmed domain) and the nearest
 * points of the face's edges, seams and collapsed edges included. The value is the distance
 * to a point of the face, so never below the true distance. */
double cb_face_distance(double uv[2], const cb_face *f, const double p[3]);

/* The outward unit normal of the face at (u, v) (S_u x S_v, turned by same_sense); returns
 * its length before normalising (0 at a pole or apex, n then undefined). */
double cb_face_normal(double n[3], const cb_face *f, double u, double v);

#endif
