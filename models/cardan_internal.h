/* cardan_internal.h — the B-rep assembly helpers shared by the Cardan-joint part builders
 * (models/build_brep.c). Not part of the public API. A part is described in its own frame;
 * the builder maps every point, direction and surface frame through the pose as it appends
 * the entities. Calls after the first failure do nothing, so a builder checks bd->st once at
 * the end (cb_build_finish). */
#ifndef CB_MODELS_CARDAN_INTERNAL_H
#define CB_MODELS_CARDAN_INTERNAL_H

#include "brep/topo.h"
#include "models/models.h"

typedef struct {
    cb_topo_body *b;
    cb_frame f; /* the pose: part coordinates -> world */
    int as_nurbs;
    double tol;
    cb_error *err;
    cb_status st; /* first failure */
} cb_build;

/* The three edges of a cylindrical arm or bore from circle c0 (at its start) to circle c1
 * (at its end), both starting at the seam line's ends. */
typedef struct {
    int c0, c1, seam;
    double o[3], dir[3], ref[3]; /* start centre, unit axis, unit seam direction */
    double r, len;
} cb_build_tube;

/* Starts a body posed by p->pose, of tolerance p->tol (or CB_CARDAN_REL_TOL size). */
cb_status cb_build_start(cb_build *bd, const cb_cardan_params *p, double size, cb_error *err);
/* One shell of every face, one solid; index, pcurves. Frees the body on failure. */
cb_status cb_build_finish(cb_topo_body **out, cb_build *bd, const char *what);

int cb_build_vertex(cb_build *bd, const double p[3]);
int cb_build_line(cb_build *bd, int v0, int v1);
/* Full circle of centre o, unit normal n, from the vertex v at o + r ref over [0, 2 pi]. */
int cb_build_circle(cb_build *bd, const double o[3], const double n[3], const double ref[3],
                    double r, int v);
/* Plane through o with unit outward normal n and in-plane axis x (face same_sense 1); as a
 * B-spline it covers [u0, u1] x [v0, v1] of the plane's (u, v) = (x.(p - o), (n x x).(p - o)). */
int cb_build_plane_face(cb_build *bd, const double o[3], const double n[3], const double x[3],
                        const double range[4]);
/* Plane face bounded by a planar polygon of part-frame points: its range is the polygon's
 * bounding rectangle in the plane's (u, v). */
int cb_build_polygon_face(cb_build *bd, const double o[3], const double n[3], const double x[3],
                          int n_pts, const double (*pts)[3]);
/* The edges of a tube from o along the unit dir, radius r, length len, seam at o + r ref. */
void cb_build_tube_edges(cb_build *bd, cb_build_tube *t, const double o[3], const double dir[3],
                         const double ref[3], double r, double len);
/* The cylindrical face of a tube: outward (solid arm) or facing its axis (bore). */
void cb_build_tube_face(cb_build *bd, const cb_build_tube *t, int outward);
/* Quarter circle of centre o, unit normal n, from v0 at o + r ref (t = 0) counter-clockwise
 * about n to v1 (t = pi/2). */
int cb_build_quarter_arc(cb_build *bd, const double o[3], const double n[3], const double ref[3],
                         double r, int v0, int v1);
/* A concave quarter-cylinder face (a fillet: the solid lies outside the cylinder, so the face
 * normal points at the axis): axis through o along the unit dir over [0, len], the quarter turn
 * counter-clockwise about dir from ref. */
void cb_build_fillet_face(cb_build *bd, const double o[3], const double dir[3],
                          const double ref[3], double r, double len);
/* The disc capping a solid arm at its end. */
void cb_build_cap_face(cb_build *bd, const cb_build_tube *t);
/* The two end faces of a profile extruded along y over [-hw, hw]: the profile's n points
 * (x, z), clockwise seen from +y; ef[k] and ek[k] the edges of segment k at y = -hw and +hw,
 * running from point k to k + 1 when fwd[k], else back. n <= 16. */
void cb_build_profile_ends(cb_build *bd, int n, const double (*pt)[2], double hw, const int *ef,
                           const int *ek, const int *fwd);
/* Appends a loop of n (edge, sense) pairs in traversal order to the last face. */
void cb_build_loop(cb_build *bd, int n, const int (*es)[2]);

/* The part builders (models/cardan_cross.c, models/cardan_yoke.c); p already checked. */
cb_status cb_cardan_build_cross(cb_topo_body **out, const cb_cardan_params *p, cb_error *err);
cb_status cb_cardan_build_yoke(cb_topo_body **out, const cb_cardan_params *p, cb_error *err);

#endif
