/* analytic.h — analytic surfaces (plane, cylinder, cone, sphere, torus, ellipsoid): placement
 * frames, evaluation with derivatives, exact implicit equations and exact rational B-spline
 * form.
 *
 * Parameterisations follow ISO 10303-42 (STEP) so that STEP faces map onto them unchanged. In
 * the local coordinates (x', y', z') of a placement frame:
 *   plane      (u, v, 0)
 *   cylinder   (r cos u, r sin u, v)
 *   cone       ((r + v tan a) cos u, (r + v tan a) sin u, v)
 *   sphere     (r cos v cos u, r cos v sin u, r sin v)
 *   torus      ((R + r cos v) cos u, (R + r cos v) sin u, r sin v)
 *   ellipsoid  (a cos v cos u, b cos v sin u, c sin v)
 * Every kind but the plane is thus (sx rho(v) cos u, sy rho(v) sin u, h(v)): a profile curve
 * (rho, h) revolved about z' and scaled by (sx, sy) (1 except for the ellipsoid); the code
 * works in that form.
 *
 * The implicit equations are the ones section 5.3 of Yang, Jia, Yan (ACM TOG 2023, "Topology
 * guaranteed B-spline surface/surface intersection") substitutes for implicitization when one
 * surface is analytic. They are dense trivariate polynomials (cb_poly3) in world coordinates,
 * or in coordinates about a chosen centre for better conditioning far from the world origin. */
#ifndef CB_ANALYTIC_H
#define CB_ANALYTIC_H

#include "brep/nurbs.h"

/* ---------------------------------------------------------------- placement frames --------- */

/* Origin o and a right-handed orthonormal frame (x, y, z), as STEP's AXIS2_PLACEMENT_3D. */
typedef struct {
    double o[3], x[3], y[3], z[3];
} cb_frame;

/* Builds f from an origin, an axis (z, normalised) and a reference direction whose component
 * perpendicular to the axis, normalised, becomes x; y = z x x. ref_dir NULL picks the world
 * axis least aligned with `axis`. Rejects non-finite input, a zero axis, and a reference
 * direction whose perpendicular component is lost in the rounding of the projection (zero or
 * parallel to the axis). Method: Gram-Schmidt with one reorthogonalisation, so the frame is
 * orthonormal to round-off. */
cb_status cb_frame_make(cb_frame *f, const double origin[3], const double axis[3],
                        const double ref_dir[3], cb_error *err);

/* World point o + l[0] x + l[1] y + l[2] z of the local coordinates l; p may alias l. */
void cb_frame_to_world(double p[3], const cb_frame *f, const double l[3]);
/* Local coordinates (x.(p-o), y.(p-o), z.(p-o)) of the world point p; l may alias p. */
void cb_frame_to_local(double l[3], const cb_frame *f, const double p[3]);

/* ---------------------------------------------------------------- surfaces ----------------- */

typedef enum {
    CB_ANALYTIC_PLANE,
    CB_ANALYTIC_CYLINDER,
    CB_ANALYTIC_CONE,
    CB_ANALYTIC_SPHERE,
    CB_ANALYTIC_TORUS,
    CB_ANALYTIC_ELLIPSOID
} cb_analytic_kind;

/* A plain value (no heap storage). Fields by kind:
 *   cylinder, sphere: r1 = radius
 *   cone:             r1 = radius at v = 0 (>= 0), angle = semi-angle a in (0, pi/2)
 *   torus:            r1 = major radius R, r2 = minor radius r
 *   ellipsoid:        r1, r2, r3 = semi-axes a, b, c along x', y', z'
 * Unused fields are 0. Build it with a constructor below, which checks the ranges. */
typedef struct {
    cb_analytic_kind kind;
    cb_frame frame;
    double r1, r2, r3;
    double angle;
} cb_analytic_surface;

/* Short fixed name of a kind ("plane", "cylinder", ...). */
const char *cb_analytic_kind_name(cb_analytic_kind kind);

/* The constructors copy the frame f (which must be right-handed orthonormal, as
 * cb_frame_make builds it) and check the shape parameters: radii finite and > 0, except the
 * cone's radius which may be 0 (STEP CONICAL_SURFACE WR1: radius >= 0, apex at the origin);
 * cone semi-angle in the open (0, pi/2). A torus may be a ring (R > r) or a spindle (R < r,
 * as some files write a screw head's dome), which meets itself on the axis: a face lies on
 * one part, the apple (R + r cos v > 0, outside) or the lemon (inside, across the axis from
 * its tube circle). A horn torus (R = r: the tube touches the axis in one point) is refused
 * with a message that says so. On failure s is left unchanged. */
cb_status cb_analytic_plane(cb_analytic_surface *s, const cb_frame *f, cb_error *err);
cb_status cb_analytic_cylinder(cb_analytic_surface *s, const cb_frame *f, double radius,
                               cb_error *err);
cb_status cb_analytic_cone(cb_analytic_surface *s, const cb_frame *f, double radius,
                           double semi_angle, cb_error *err);
cb_status cb_analytic_sphere(cb_analytic_surface *s, const cb_frame *f, double radius,
                             cb_error *err);
cb_status cb_analytic_torus(cb_analytic_surface *s, const cb_frame *f, double major_radius,
                            double minor_radius, cb_error *err);
cb_status cb_analytic_ellipsoid(cb_analytic_surface *s, const cb_frame *f, double a, double b,
                                double c, cb_error *err);

/* The point S(u, v) of the parameterisation above; any finite (u, v) is accepted (u is
 * periodic, and a sphere v outside [-pi/2, pi/2] still lands on the sphere). */
void cb_analytic_eval(double p[3], const cb_analytic_surface *s, double u, double v);

/* d[0] = S, d[1] = S_u, d[2] = S_v, d[3] = S_uu, d[4] = S_uv, d[5] = S_vv (the layout of
 * cb_nurbs_surface_eval_derivs); d[0] equals cb_analytic_eval bit for bit. */
void cb_analytic_eval_derivs(double d[6][3], const cb_analytic_surface *s, double u, double v);

/* ---------------------------------------------------------------- trivariate polynomials --- */

/* Dense polynomial sum c[idx(i,j,k)] x^i y^j z^k over i + j + k <= deg. The layout is graded
 * and independent of deg: monomials by total degree t = i + j + k, then within a degree by
 * m = j + k, then by k (x^t, x^(t-1) y, x^(t-1) z, x^(t-2) y^2, ...), so
 *   idx(i, j, k) = t (t + 1) (t + 2) / 6 + m (m + 1) / 2 + k,
 * and a polynomial of degree d is a prefix of the same polynomial stored at degree d + 1.
 * deg is the storage degree, an upper bound on the true degree; deg = -1 (after _init) is the
 * zero polynomial with no storage. */
typedef struct {
    int deg;
    double *c;
} cb_poly3_struct;
typedef cb_poly3_struct cb_poly3_t[1];

/* Largest storage degree accepted; keeps every index far from int overflow. */
#define CB_POLY3_MAX_DEGREE 64

/* Number of coefficients of degree deg: (deg + 1) (deg + 2) (deg + 3) / 6. */
static inline int cb_poly3_len(int deg) { return (deg + 1) * (deg + 2) * (deg + 3) / 6; }

static inline int cb_poly3_index(int i, int j, int k)
{
    int t = i + j + k, m = j + k;
    return t * (t + 1) * (t + 2) / 6 + m * (m + 1) / 2 + k;
}

void cb_poly3_init(cb_poly3_t p);
void cb_poly3_clear(cb_poly3_t p);
void cb_poly3_swap(cb_poly3_t a, cb_poly3_t b);
/* Resizes p to storage degree deg in [0, CB_POLY3_MAX_DEGREE], every coefficient zero. */
cb_status cb_poly3_alloc(cb_poly3_t p, int deg, cb_error *err);
cb_status cb_poly3_set(cb_poly3_t dst, const cb_poly3_t src, cb_error *err);

/* p(x) by the monomial sum with power tables (degree 4 needs no Horner scheme). */
double cb_poly3_eval(const cb_poly3_t p, const double x[3]);
/* p(x) and its gradient. */
double cb_poly3_eval_grad(double grad[3], const cb_poly3_t p, const double x[3]);

/* out = a b at storage degree a->deg + b->deg (or the zero polynomial if either is); out may
 * alias a or b. */
cb_status cb_poly3_mul(cb_poly3_t out, const cb_poly3_t a, const cb_poly3_t b, cb_error *err);

/* out(x) = p(m x + t): the affine substitution of each variable, same storage degree; out may
 * alias p. Method: powers of the three affine forms, accumulated monomial by monomial. */
cb_status cb_poly3_compose_affine(cb_poly3_t out, const cb_poly3_t p, const double m[3][3],
                                  const double t[3], cb_error *err);

/* ---------------------------------------------------------------- implicit equations ------- */

/* F with F(p) = 0 exactly on the surface (up to the rounding of the coefficients), in world
 * coordinates p: the local equation below with x' = X.(p - O), y' = Y.(p - O), z' = Z.(p - O)
 * substituted (cb_poly3_compose_affine). rho = sqrt(x'^2 + y'^2) is the distance from the axis.
 *   plane      z'                                             degree 1
 *   cylinder   (x'^2 + y'^2 - r^2) / (2 r)                    degree 2
 *   sphere     (x'^2 + y'^2 + z'^2 - r^2) / (2 r)             degree 2
 *   ellipsoid  (m / 2)(x'^2/a^2 + y'^2/b^2 + z'^2/c^2 - 1), m = min(a, b, c)
 *   cone       (cos a / 2)(x'^2 + y'^2 - (r + z' tan a)^2)    degree 2
 *   torus      ((x'^2 + y'^2 + z'^2 + R^2 - r^2)^2 - 4 R^2 (x'^2 + y'^2)) / (8 R r)   degree 4
 * Normalisation: on the surface, |grad F| = 1 for the plane, cylinder and sphere (F is the
 * signed distance to first order, exactly for the plane); |grad F| in [min/max, 1] of the
 * semi-axes for the ellipsoid (it reduces to the sphere when a = b = c); |grad F| = rho for
 * the cone and the torus, whose gradients cannot be constant (the cone's vanishes at the apex),
 * so F / rho is the signed distance to first order. F > 0 outside (away from the axis or
 * centre; on the +z' side of the plane). The cone's equation holds on both nappes.
 *
 * Conditioning: F(p) in world coordinates carries rounding of order eps sum |c| |p|^alpha over
 * its terms, which far from the world origin exceeds the size of F near the surface: for a
 * torus at distance D from the origin the error in F / |grad F| grows like eps D^4 / (R r rho).
 * Where that matters use cb_analytic_implicit_about with a center near the region of interest;
 * its coefficients are computed from the local equation directly, not by shifting F. */
cb_status cb_analytic_implicit(cb_poly3_t F, const cb_analytic_surface *s, cb_error *err);

/* The same equation in the coordinates q = p - center: F(q) = 0 iff center + q is on s. */
cb_status cb_analytic_implicit_about(cb_poly3_t F, const cb_analytic_surface *s,
                                     const double center[3], cb_error *err);

/* ---------------------------------------------------------------- rational B-spline form --- */

/* The arc t -> center + radius (cos t xdir + sin t ydir), t in [a0, a1], as an exact rational
 * quadratic B-spline: n = 1..4 equal segments of at most pi/2, joined by double knots, with
 * domain [a0, a1] and knots at the segment angles, where the B-spline parameter equals t.
 * xdir, ydir are used as given: orthonormal gives the circle of that radius, any other
 * independent pair the ellipse that is its affine image (still exact). Rejects non-finite
 * input, radius <= 0, xdir and ydir zero or parallel, a0 >= a1 and a1 - a0 > 2 pi (a full
 * circle, a1 = a0 + 2 pi as computed in double, is allowed). Method: The NURBS Book A7.1. */
cb_status cb_nurbs_curve_arc(cb_nurbs_curve_t c, const double center[3], const double xdir[3],
                             const double ydir[3], double radius, double a0, double a1,
                             cb_error *err);

/* The same arc with exact data where its range allows it, as cb_analytic_to_nurbs_exact
 * writes the angular directions: segments that are quarter turns from one whole quarter angle
 * to the next get the unit arc's control points 0, +-1, +-2 and weights 1, 1, 2 (times powers
 * of 2), the tangent-half-angle form; other ranges as cb_nurbs_curve_arc. The B-spline
 * parameter equals t at the knots only (cb_nurbs_arc_angle maps it to t). Same checks. */
cb_status cb_nurbs_curve_arc_exact(cb_nurbs_curve_t c, const double center[3],
                                   const double xdir[3], const double ydir[3], double radius,
                                   double a0, double a1, cb_error *err);

/* The angle t of the point at B-spline parameter s of the arc that cb_nurbs_curve_arc (exact
 * = 0) or cb_nurbs_curve_arc_exact (exact = 1) builds over [a0, a1], and likewise of every
 * angular direction of cb_analytic_to_nurbs(_exact) and cb_nurbs_surface_revolve: closed form
 * (the rational Bezier segment evaluated at s, its angle from the segment's first point by
 * atan2). Continuous and strictly increasing from [a0, a1] onto [a0, a1], equal to s at the
 * knots, so it maps the B-spline's parameters bijectively onto the angles. s outside [a0, a1]
 * is clamped to it. */
double cb_nurbs_arc_angle(double a0, double a1, int exact, double s);

/* The surface swept by turning the curve profile by the angles u in [a0, a1] (at most one
 * turn) about the axis through o along the unit vector z: S(u, v) = profile(v) turned by u,
 * as an exact rational B-spline of degree (2, profile degree). u is the arc of
 * cb_nurbs_curve_arc (exact = 0) or cb_nurbs_curve_arc_exact (exact = 1) over [a0, a1] (the
 * angle at the knots, cb_nurbs_arc_angle between them), v the profile's own parameter and
 * knots. The profile need not be planar nor lie in a plane through the axis: turning is affine
 * in (cos u, sin u), so the control net is the unit arc's applied to each profile point, and
 * the weights multiply (The NURBS Book A8.1). Profile points on the axis give collapsed rows
 * (poles). Rejects a non-finite axis, |z| not 1 within 1e-12, and angle ranges as
 * cb_nurbs_curve_arc. */
cb_status cb_nurbs_surface_revolve(cb_nurbs_surface_t out, const cb_nurbs_curve_t profile,
                                   const double o[3], const double z[3], double a0, double a1,
                                   int exact, cb_error *err);

/* The parabola arc t -> vertex + focal (t^2 xdir + 2 t ydir), t in [t0, t1] (ISO 10303-42's
 * PARABOLA with focal distance focal), as one quadratic Bezier segment with knots
 * (t0, t0, t0, t1, t1, t1): a parabola is a polynomial curve, so the B-spline parameter equals t
 * everywhere. Control points C(t0), vertex + focal (t0 t1 xdir + (t0 + t1) ydir) (where the end
 * tangents meet), C(t1). Rejects non-finite input, focal <= 0, xdir and ydir zero or parallel,
 * t0 >= t1. */
cb_status cb_nurbs_curve_parabola(cb_nurbs_curve_t c, const double vertex[3],
                                  const double xdir[3], const double ydir[3], double focal,
                                  double t0, double t1, cb_error *err);

/* The hyperbola arc t -> center + a cosh t xdir + b sinh t ydir, t in [t0, t1] (one branch, as
 * ISO 10303-42's HYPERBOLA), as an exact rational quadratic B-spline: n equal segments of
 * length at most 2 joined by double knots at their t values (the B-spline parameter equals t
 * there, not between). On a segment [s, s'] with mid m and half-length h the control points
 * are C(s), center + (a cosh m xdir + b sinh m ydir) / cosh h (where the end tangents meet),
 * C(s') and the middle weight cosh h: the hyperbolic rotation by m of the symmetric arc
 * [-h, h], whose midpoint (a, 0) fixes the weight. Rejects non-finite input, a or b <= 0,
 * xdir and ydir zero or parallel, t0 >= t1, |t0| or |t1| > 700 (cosh overflows). */
cb_status cb_nurbs_curve_hyperbola(cb_nurbs_curve_t c, const double center[3],
                                   const double xdir[3], const double ydir[3], double a, double b,
                                   double t0, double t1, cb_error *err);

/* An exact rational B-spline surface whose image is s over [u0, u1] x [v0, v1]:
 *   plane                     degree (1, 1), bilinear
 *   cylinder, cone            degree (2, 1): arc in u times a line in v (the cone's radius is
 *                             linear in v, so the ruling is exact)
 *   sphere, ellipsoid, torus  degree (2, 2): parallel arc in u times meridian arc in v (the
 *                             ellipsoid is the sphere scaled along the axes: affine maps act on
 *                             homogeneous control points exactly)
 * The domain is [u0, u1] x [v0, v1] and each angular direction is split as cb_nurbs_curve_arc
 * splits it; at every knot pair the B-spline parameter equals (u, v), in particular at the four
 * corners, and between knots it differs but the image is the same. Rejects non-finite or empty
 * ranges, an angular range longer than 2 pi (u for all but the plane, v for the torus), a
 * sphere or ellipsoid v outside [-pi/2, pi/2], and a cone v range that crosses the apex
 * v = -r / tan a strictly (a range ending at the apex gives a collapsed edge, as do the poles). */
cb_status cb_analytic_to_nurbs(cb_nurbs_surface_t out, const cb_analytic_surface *s, double u0,
                               double u1, double v0, double v1, cb_error *err);

/* The same surface with exact data where the angular ranges allow it: an angular direction
 * whose arc segments are quarter turns from one whole quarter angle to the next (a full turn
 * from 0, the latitudes [-pi/2, pi/2]) gets control points and weights exact in binary (end
 * points on the axes, middle points at the corners of the circumscribed square, weights 1, 1,
 * 2 per segment times powers of 2: the tangent-half-angle form of the quarter circle), not
 * cos(pi/4) rounded; other ranges as cb_analytic_to_nurbs. An exact SSI of the converted
 * surface against another exact surface then sees the tangencies of the analytic ones (rounded
 * weights move a contact by an ulp, into a near-miss or a crossing that no certificate can
 * settle). The B-spline parameter equals (u, v) at the knots only, as above, and differs more
 * between them (the weights are not symmetric). */
cb_status cb_analytic_to_nurbs_exact(cb_nurbs_surface_t out, const cb_analytic_surface *s,
                                     double u0, double u1, double v0, double v1, cb_error *err);

#endif
