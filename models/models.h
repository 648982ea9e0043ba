/* models.h — generators of the models Colibri ships for its Boolean scenarios.
 *
 * Each generator builds a new closed solid as a B-rep body (brep/topo.h) from a few shape and
 * pose parameters, so that two copies in different poses make a Boolean test case. The bodies
 * are indexed (cb_topo_body_index) and pass cb_topo_validate at the body's own tolerance. */
#ifndef CB_MODELS_H
#define CB_MODELS_H

#include "brep/topo.h"

/* ---------------------------------------------------------------- hummingbird -------------- */

/* The model is built in its own frame (x forward to the beak, y to the left wing, z up), about
 * 2.9 long, 2.9 across the wings and 1.1 high at scale 1 with the default wing angle, then
 * scaled about the origin, rotated about the axis through the origin and translated:
 * p -> R(axis, angle) (scale p) + translate. */
typedef struct {
    double scale;          /* > 0 */
    double wing_angle_deg; /* dihedral: wings raised above the horizontal, in [-30, 50] */
    double axis[3];        /* rotation axis, any nonzero length (ignored when angle_deg = 0) */
    double angle_deg;      /* rotation angle, degrees, right-handed about axis */
    double translate[3];
} cb_hummingbird_params;

/* Scale 1, wings raised 20 degrees, no rotation, no translation. */
void cb_hummingbird_params_default(cb_hummingbird_params *p);

/* Builds a closed freeform bird-shaped solid — body, head and beak, two wings, tail — of 312
 * faces, each a clamped bicubic B-spline with 6 x 6 control points and knots
 * {0,0,0,0,1/3,2/3,1,1,1,1} both ways, as in the paper's Fig. 12 (Yang, Jia, Yan, "Topology
 * guaranteed B-spline surface/surface intersection", ACM TOG 2023: two birds of 312 patches).
 *
 * Layout: the surface of the box [-5,5] x [-3,3] x [-3,3] cut into unit squares (312 quads,
 * 314 vertices, 624 edges), mapped onto a star-shaped guide surface (an ellipsoid with lobes
 * for head, beak, wings and tail) bent by a volume-preserving shear; see hummingbird.c.
 * Continuity: C2 between faces that come from the same box side, C0 (G1 up to the fit error)
 * across the box's 12 edges. Watertight: two faces sharing an edge hold bit-identical control
 * rows along it, which are the edge's curve; the face corners are the vertices. Every face has
 * same_sense = 1 with S_u x S_v pointing out of the solid. The body tolerance (b->tol and
 * every edge's tol) is 1e-9 times the scale.
 *
 * Fails with CB_ERR_INVALID for parameters out of range, CB_ERR_NUMERIC if the fitted surface
 * fails the no-fold check (cb_model_hummingbird_margin below, 12 x 12 samples per face, margin
 * below 0.01), CB_ERR_NOMEM. *out is NULL on failure. */
cb_status cb_model_hummingbird(cb_topo_body **out, const cb_hummingbird_params *p, cb_error *err);

/* Evidence that a body built by cb_model_hummingbird with the same parameters does not
 * intersect itself. The model is star-shaped before its shear: pulled back through the pose,
 * the scale and the shear, every point q of the surface must see the origin from outside,
 * q . n'(q) > 0 with n' the pulled-back outward normal. Then the radial projection of the
 * pulled-back surface onto the unit sphere is a local homeomorphism of a closed surface onto
 * the sphere, hence one-to-one: the surface is embedded, and so is its image under the
 * (bijective) shear and the rigid motion. *margin receives the smallest cosine q . n' /
 * (|q| |n'|) over an n x n grid of parameters per face (n >= 2, the face boundary included).
 * CB_ERR_INVALID when the body is not a hummingbird of 312 B-spline faces. */
cb_status cb_model_hummingbird_margin(double *margin, const cb_topo_body *b,
                                      const cb_hummingbird_params *p, int n, cb_error *err);

#endif
