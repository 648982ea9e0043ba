/* models.h — generators of the models Colibri ships for its Boolean scenarios.
 *
 * Each generator builds a new closed solid as a B-rep body (brep/topo.h) from a few shape and
 * pose parameters, so that two copies in different poses make a Boolean test case. The bodies
 * are indexed (cb_topo_body_index) and pass cb_topo_validate at the body's own tolerance. */
#ifndef CB_MODELS_H
#define CB_MODELS_H

#include "brep/nurbs.h"
#include "brep/topo.h"

/* ---------------------------------------------------------------- volume estimates --------- */

/* Volumes from cb_model_overlap_estimate: V(A), V(B), V(A n B) and the standard deviation of
 * each estimate; lines: how many vertical lines were followed (retries included). */
typedef struct {
    double volume_a, volume_b, volume_ab;
    double sigma_a, sigma_b, sigma_ab;
    long lines, retries;
} cb_overlap_estimate;

/* |cos| of the angle between a line and a face normal below which a crossing is not trusted
 * and the line is drawn again. */
#define CB_OVERLAP_GRAZE_COS 1e-3

/* Estimates V(A), V(B) and V(A n B) of two closed solids (every coedge with a pcurve) by a
 * method that knows nothing of Booleans: the xy rectangle holding both is cut into n x n cells,
 * and through one random point of each cell (a fixed sequence: the same numbers on any number
 * of threads) the vertical line is intersected with every face (cb_face_ray); the lengths it
 * spends inside A, inside B and inside both, times the cell area, summed over the cells, are
 * unbiased estimates of the three volumes (stratified sampling). A line whose crossings graze,
 * touch an edge, or do not alternate between entering and leaving (a missed root) is drawn again
 * in its cell, up to 8 times. The standard deviations come from the differences of neighbouring
 * cells (an upper bound in expectation). The error of a result is the sampling error only if no
 * line misses a pair of crossings; cb_face_ray's cell boxes are a heuristic (brep/face.h).
 * n: even, 2 <= n <= 20000; threads as in cb_parallel_for. CB_ERR_NUMERIC when every line
 * through a cell failed, CB_ERR_INVALID for n, CB_ERR_NOMEM. */
cb_status cb_model_overlap_estimate(cb_overlap_estimate *e, const cb_topo_body *A,
                                    const cb_topo_body *B, int n, int threads, cb_error *err);

/* ---------------------------------------------------------------- paper surfaces ----------- */

/* The surface pair of Example 2 of the SSI paper (../shared/reference/topology-guaranteed-ssi.md,
 * appendix A): P, the rational bicubic of its Example 1 over [0, 1]^2, and Q(s, t) = [2st^2 + 2s,
 * -s^2t^3 + s^2 - 3t^3 + 3, 2s^3t + 6t, s^2t^2 + s^2 + t^2 + 1] over [-1, 1] x [0, 2], as
 * single-patch rational B-splines whose homogeneous control points are integers (the exact
 * Bernstein coefficients times 36). P and Q must be initialised; errors of
 * cb_nurbs_surface_alloc. */
cb_status cb_model_paper_example2(cb_nurbs_surface_t P, cb_nurbs_surface_t Q, cb_error *err);

/* ---------------------------------------------------------------- graph pairs -------------- */

/* Largest degree in each variable of a cb_model_poly. */
#define CB_MODEL_POLY_DEG 8

/* The integer polynomial sum c[i][j] u^i v^j. overflow: some operation that built it left the
 * 64-bit integers (the coefficients are then meaningless). */
typedef struct {
    long long c[CB_MODEL_POLY_DEG + 1][CB_MODEL_POLY_DEG + 1];
    int overflow;
} cb_model_poly;

/* a u + b v + c */
cb_model_poly cb_model_poly_linear(long long a, long long b, long long c);
/* a b; terms beyond CB_MODEL_POLY_DEG set overflow */
cb_model_poly cb_model_poly_mul(const cb_model_poly *a, const cb_model_poly *b);
/* a + k b */
cb_model_poly cb_model_poly_add(const cb_model_poly *a, const cb_model_poly *b, long long k);
/* (a u - b)^2 + (a v - c)^2 - r2: the circle of radius sqrt(r2) / a about (b / a, c / a), or
 * for r2 = 0 the point (a double root, an isolated zero) */
cb_model_poly cb_model_poly_circle(long long a, long long b, long long c, long long r2);
double cb_model_poly_eval(const cb_model_poly *p, double u, double v);

/* A graph pair (the SSI issue's test surfaces): over the square (u, v) in [0, 1]^2 of the xy
 * plane, P is the graph of S f, f(u, v) = (u - 1/2)(v - 1/2) + (u - 1/2)^2 / 2 - (v - 1/2)^2 / 4,
 * and Q the graph of S (f + h / 2^height_shift), both moved by one rigid motion (a third of a
 * turn about (1, 1, 1), then a translation). So P and Q meet exactly where h vanishes, lifted
 * to P: cb_model_graph_point. S in [1/2, 1) is an odd integer times a power of two that makes
 * every control point exact in binary, so tangencies designed into h (double roots) are
 * tangencies of the stored surfaces. */
typedef struct {
    double scale;     /* S */
    int height_shift; /* |h| / 2^height_shift <= 1/4 on the square */
} cb_model_graph;

/* The interior knots: P's (u, v) = (9/16, 5/16), Q's (s, t) = (13/16, -5/32), that is
 * y = 19/32 and x = 27/64 (one per direction, so that Bezier extraction stays exact). */
#define CB_MODEL_GRAPH_KNOT_P ((const double[2]){0.5625, 0.3125})
#define CB_MODEL_GRAPH_KNOT_Q ((const double[2]){0.8125, -0.15625})

/* P: biquadratic, parameters (u, v) on [0, 1]^2, with x = u, y = v. Q: parametrised
 * differently, with its own degrees (those of h, at least 2): its first parameter s in [0, 2]
 * runs along y reversed (y = 1 - s / 2), its second t in [-1, 1] along x (x = (t + 1) / 2).
 * Each has one interior knot per direction (above). P and Q must be initialised.
 * CB_ERR_INVALID when h overflowed or its degrees or coefficients are too large for the control
 * points to be exact; CB_ERR_NOMEM. */
cb_status cb_model_graph_pair(cb_nurbs_surface_t P, cb_nurbs_surface_t Q, cb_model_graph *g,
                              const cb_model_poly *h, cb_error *err);
/* The point of P (moved) over (u, v): where the curve h(u, v) = 0 lies in space. */
void cb_model_graph_point(double X[3], const cb_model_graph *g, double u, double v);

/* ---------------------------------------------------------------- graph cases (SSI corpus) - */

/* Cases of the randomized SSI corpus (graph_generic.c; issue 22, class 2): two whole B-spline
 * surfaces P and Q whose intersection is a designed curve, in three poses. Over the design
 * square (x, y) in [0, 1]^2, P is the graph of a height f and Q the graph of f + h, so that
 * they meet exactly where the designed polynomial h vanishes; the classes of h cover the
 * paper's Fig. 1 (crossing, isolated contacts, boundary curves, touching branches, tangential
 * curves, several contacts) and more (cusps, nodes, small and close loops, several components).
 * A point (x, y, z) of the design space is in the world at R diag(L) (x, y, z) + T.
 *
 * Poses:
 *   EXACT    cb_model_graph_pair: f its biquadratic, h an integer polynomial (parameters on a
 *            dyadic grid), every control point exact in binary, a motion that permutes axes;
 *   PARAM    the generic surfaces below, moved by a rotation that permutes (and flips) axes
 *            and a dyadic translation;
 *   GENERIC  f a random spline of bidegree (3, 3) (sometimes (4, 4), (5, 3), (3, 5)) with random
 *            interior knots (none of them dyadic; in half the cases none, and P and Q get
 *            knots of their own instead) and random control values; h with random
 *            parameters; Q = f + h degree-elevated to h's degrees, with knots of its own, often
 *            over a larger rectangle than P's square; P sometimes elevated or refined once
 *            more; each parametrised by its own affine maps (non-dyadic scales and offsets,
 *            reversal, transposition); both moved by one random rigid motion (a random unit
 *            quaternion, a random translation) after a random scaling of the design axes.
 * Every case is built from (class, pose, index) alone: deterministic on any machine. The
 * stored surfaces differ from the design by rounding (about 1e-16 of their size), far below
 * the SSI's tolerance (1e-6 of the size): the truth is the designed curve, within tolerance. */
typedef enum {
    CB_GRAPH_CLASS_LOOP,             /* one transversal loop */
    CB_GRAPH_CLASS_TWO_LOOPS,        /* two disjoint loops */
    CB_GRAPH_CLASS_CLOSE_LOOPS,      /* two loops a small gap apart */
    CB_GRAPH_CLASS_CROSSING_LOOPS,   /* Fig. 1a: two loops crossing at two nodes */
    CB_GRAPH_CLASS_NODE,             /* two lines crossing at a node */
    CB_GRAPH_CLASS_CUSP,             /* a semicubical cusp */
    CB_GRAPH_CLASS_CONTACT_BRANCHES, /* Fig. 1b: an isolated contact between two branches */
    CB_GRAPH_CLASS_BOUNDARY,         /* Fig. 1c: two boundary sides and an arc */
    CB_GRAPH_CLASS_TANGENT_SIDES,    /* Fig. 1d: four boundary sides and a tangential line */
    CB_GRAPH_CLASS_LOOPS_TOUCHING,   /* Fig. 1e: two loops touching at one point */
    CB_GRAPH_CLASS_TANGENTIAL_LOOP,  /* Fig. 1f: contact along a whole loop */
    CB_GRAPH_CLASS_TANGENTIAL_LINE,  /* contact along a curve across the square */
    CB_GRAPH_CLASS_CONTACTS,         /* Fig. 1g: several isolated contact points */
    CB_GRAPH_CLASS_SMALL_LOOP,       /* a loop of radius 1e-3 to 4e-3 */
    CB_GRAPH_CLASS_MULTI,            /* a loop, an open branch and an isolated contact */
    CB_GRAPH_CLASS_COUNT
} cb_graph_class;

typedef enum { CB_GRAPH_POSE_EXACT, CB_GRAPH_POSE_PARAM, CB_GRAPH_POSE_GENERIC,
               CB_GRAPH_POSE_COUNT } cb_graph_pose;

/* Short names ("tangential_loop", "generic") and the Fig. 1 panel of a class ("1f" or "-"). */
const char *cb_graph_class_name(int cls);
const char *cb_graph_class_fig(int cls);
const char *cb_graph_pose_name(int pose);

/* A piece of the designed curve h = 0 in the design plane (clipped to the square when used):
 *   CIRCLE  centre (a[0], a[1]), radius a[2];
 *   LINE    through (a[0], a[1]) with direction angle a[2];
 *   CUSP    (y')^2 = a[3] (x')^3 in the frame at (a[0], a[1]) turned by a[2];
 *   POINT   (a[0], a[1]): an isolated contact. */
typedef enum { CB_GRAPH_CIRCLE, CB_GRAPH_LINE, CB_GRAPH_CUSP, CB_GRAPH_POINT } cb_graph_prim_kind;

typedef struct {
    cb_graph_prim_kind kind;
    double a[4];
    int tangential; /* on a squared factor of h: the surfaces touch along it */
} cb_graph_prim;

#define CB_GRAPH_MAX_PRIMS 6
#define CB_GRAPH_MAX_SINGULAR 8

typedef struct {
    int cls, pose, index;
    char id[64]; /* "class/pose/index" */
    cb_nurbs_surface_t P, Q;  /* the pair, in the world */
    cb_nurbs_surface_t F;     /* the design height: F(x, y) = (x, y, f(x, y)) over a rectangle
                                 holding the square, unmoved */
    double h[CB_MODEL_POLY_DEG + 1][CB_MODEL_POLY_DEG + 1]; /* Q's height minus P's, power
                                                               basis: sum h[i][j] x^i y^j */
    double R[3][3], T[3], L[3]; /* design to world: R diag(L) p + T */
    cb_graph_prim prim[CB_GRAPH_MAX_PRIMS];
    int n_prims;
    double singular[CB_GRAPH_MAX_SINGULAR][2]; /* nodes, cusps, points where branches touch or
                                                  a tangential curve meets another branch */
    int n_singular;
    int closed, open, points; /* true components: closed curves (touching no side), curves
                                 reaching the square's sides, isolated points */
    char truth[80];           /* in words */
    double size;              /* diagonal of the box of both control nets */
    int shared_knots;         /* generic poses: interior knot lines of f inside the square,
                                 which P and Q share (Q = f + h has f's breaks) */
    int q_larger;             /* generic poses: Q spans a rectangle larger than the square */
} cb_graph_case;

void cb_graph_case_init(cb_graph_case *c);
void cb_graph_case_clear(cb_graph_case *c);
/* Builds case (cls, pose, index) into c (replacing what it held). CB_ERR_INVALID for a class
 * or pose out of range, or when the exact pose's generator refuses the designed polynomial;
 * errors of the B-spline operations. */
cb_status cb_graph_case_make(cb_graph_case *c, int cls, int pose, int index, cb_error *err);
/* World point X to design coordinates p = (x, y, z). */
void cb_graph_case_design(double p[3], const cb_graph_case *c, const double X[3]);
/* The point of P over the design point (x, y), in the world. */
void cb_graph_case_lift(double X[3], const cb_graph_case *c, double x, double y);
/* Vertical distances (along the moved design z axis, world units) of X from P and from Q:
 * upper bounds of its distances to the two graphs (over (x, y) clamped to the square). */
void cb_graph_case_residual(double *dp, double *dq, const cb_graph_case *c, const double X[3]);
/* Design-plane point of primitive k at parameter s (circle: angle; line: signed length from
 * its point; cusp: sigma with x' = sigma^2, y' = sqrt(a[3]) sigma^3) and its parameter range
 * wide enough to cross the square ([0, 0] for a point). */
void cb_graph_prim_point(double xy[2], const cb_graph_prim *p, double s);
void cb_graph_prim_range(double *s0, double *s1, const cb_graph_prim *p);

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

/* ---------------------------------------------------------------- two birds ---------------- */

/* The Boolean scenario of the paper's Fig. 12: bird A with the default parameters, bird B the
 * same moved by (0.25, 0.08, 0.05), so that wings, body and head cross one another. */
void cb_hummingbird_pair(cb_hummingbird_params *a, cb_hummingbird_params *b);

/* The pair's volumes by cb_model_overlap_estimate with a grid of
 * CB_HUMMINGBIRD_PAIR_GRID^2 lines (run by `colibri model hummingbird-pair --estimate N`;
 * models/README.md): the estimates and their standard deviations. */
#define CB_HUMMINGBIRD_PAIR_GRID 4000
extern const cb_overlap_estimate cb_hummingbird_pair_reference;

/* ---------------------------------------------------------------- Cardan joint ------------- */

/* The parts of a Cardan (universal) joint, as in the paper's Fig. 13: the cross (spider) and
 * the yoke (fork), each one closed solid of planes and circular cylinders, exactly
 * constructible without Booleans, so that their volumes and those of the named Boolean
 * scenarios below have closed forms (models/README.md derives them).
 *
 * Cross, in its own frame: the cube [-a, a]^3 with four arms along +x, -x, +y, -y, each a
 * solid cylinder of radius r from the cube face (distance a from the centre) to a planar disc
 * cap at distance L. 14 faces (6 planes of the cube, those at x = +-a and y = +-a with one
 * circular inner loop each; 4 cylinders; 4 discs), 24 edges (12 lines of the cube, per arm two
 * circles and the seam line), 16 vertices. The seam of the arm along d lies on its line
 * towards z x d (its left side seen from +z), away from the scenarios' tangent contacts.
 * Volume 8 a^3 + 4 pi r^2 (L - a).
 *
 * Yoke, in its own frame: the U profile in the xz plane (base [-B, B] x [0, t], arms
 * [-B, -g] x [t, H] and [g, B] x [t, H]), its two inner corners (+-g, t) rounded by concave
 * quarter-circle fillets of radius f (f = 0: sharp), extruded over y in [-w/2, w/2]; one bore
 * of radius rb along the x axis at height hb through each arm (x in [-B, -g] and [g, B]); a
 * shaft, the solid cylinder of radius rs about the -z axis from z = 0 to z = -ls ending in a
 * disc. With fillets: 16 faces (8 planar sides of the extrusion, 4 of them with a bore circle
 * as inner loop and the bottom one with the shaft circle; 2 quarter-cylinder fillets, facing
 * their axis, tangent to the faces beside them; 2 U-shaped end faces; 2 bore cylinders, facing
 * the axis; the shaft cylinder and its disc), 39 edges (20 lines and 4 quarter circles of the
 * extrusion, 6 lines along y; per bore and for the shaft two circles and a seam), 26 vertices,
 * 21 loops. Without: 14 faces, 33 edges, 22 vertices, 19 loops. Genus 2 (the bores). Bore
 * seams lie on their bottom (-z) line, the shaft's on its +x line. Volume
 * w (2 B t + 2 (B - g)(H - t) + 2 (1 - pi/4) f^2) + pi rs^2 ls - 2 pi rb^2 (B - g).
 *
 * Pose, as the hummingbird's: p -> R(axis, angle) p + translate, applied to the part built in
 * its own frame. as_nurbs = 0 keeps every face analytic (planes, cylinders); 1 writes every
 * face as an exact rational B-spline: planes as bilinear patches over the face's bounding
 * rectangle, cylinders as degree (2, 1) patches whose circle is four (a fillet: one) rational
 * quadratic quarter arcs with control points (r, 0), (r, r), (0, r), (-r, r), ... and weights
 * 1, 1, 2, 1, 1, 1, 2, 1, 1 (exact, unlike sqrt(2)/2: in the part's own frame every control
 * point and weight is a dyadic rational when the sizes are), knots {0,0,0,1,1,2,2,3,3,4,4,4}
 * ({0,0,0,1,1,1} for a fillet) in u and the axial length in v. Edge curves are lines and
 * circles either way. Every coedge has a pcurve (cb_topo_compute_pcurves); the body is indexed
 * and passes cb_topo_validate at its tolerance with no problem. */

typedef enum { CB_CARDAN_CROSS, CB_CARDAN_YOKE } cb_cardan_kind;

typedef struct {
    double half_size;  /* a > 0: the central cube [-a, a]^3 */
    double arm_radius; /* r, 0 < r < a */
    double arm_reach;  /* L > a: distance of the arm caps from the centre */
} cb_cross_shape;

typedef struct {
    double half_span;     /* B > 0: the profile spans x in [-B, B] */
    double gap;           /* g, 0 < g < B: the arms' inner faces lie at x = +-g */
    double base_height;   /* t > 0: the base spans z in [0, t] */
    double height;        /* H > t: the arms end at z = H */
    double width;         /* w > 0: the extrusion spans y in [-w/2, w/2] */
    double bore_radius;   /* rb, 0 < rb < w/2 */
    double bore_height;   /* hb: the bore axis, with t + f < hb - rb and hb + rb < H */
    double shaft_radius;  /* rs, 0 < rs < min(B, w/2) */
    double shaft_length;  /* ls > 0 */
    double fillet_radius; /* f, 0 <= f < g and t + f < H; 0: no fillets */
} cb_yoke_shape;

typedef struct {
    double axis[3];   /* rotation axis, any nonzero length (ignored when angle_deg = 0) */
    double angle_deg; /* right-handed about axis, through the origin */
    double translate[3];
} cb_model_pose;

typedef struct {
    cb_cardan_kind kind;
    cb_cross_shape cross; /* used when kind is CB_CARDAN_CROSS */
    cb_yoke_shape yoke;   /* used when kind is CB_CARDAN_YOKE */
    cb_model_pose pose;
    int as_nurbs;
    double tol; /* body and edge tolerance; <= 0 selects CB_CARDAN_REL_TOL times the part's
                   largest extent */
} cb_cardan_params;

#define CB_CARDAN_REL_TOL 1e-9

/* The shapes the scenarios use, no rotation, no translation, analytic faces, default
 * tolerance. Cross: a = 1, r = 3/8, L = 3. Yoke: B = 5/2, g = 3/2, t = 1, H = 4, w = 4,
 * rb = 3/8 (the cross arms fit the bores), hb = 3, rs = 1, ls = 2, f = 1/2. */
void cb_cardan_params_default(cb_cardan_params *p, cb_cardan_kind kind);

/* Checks the shape ranges above, the pose (finite, nonzero axis when rotating) and tol
 * (finite); CB_ERR_INVALID naming the parameter otherwise. */
cb_status cb_cardan_params_check(const cb_cardan_params *p, cb_error *err);

/* Builds the part. Fails with CB_ERR_INVALID as cb_cardan_params_check, CB_ERR_NOMEM,
 * CB_ERR_NUMERIC if the pcurves cannot be fitted; *out is NULL on failure. */
cb_status cb_model_cardan(cb_topo_body **out, const cb_cardan_params *p, cb_error *err);

/* The part's volume by its closed form (pose-independent). CB_ERR_INVALID as _check. */
cb_status cb_model_cardan_volume(double *volume, const cb_cardan_params *p, cb_error *err);

/* A named Boolean scenario: two posed parts A and B and what makes the pair hard. */
typedef struct {
    const char *name;
    const char *contact;     /* one sentence: the contacts and overlaps of A and B */
    const char *closed_form; /* the formula of V(A n B) (derived in models/README.md) */
    cb_cardan_params a, b;
} cb_cardan_scenario;

/* Volumes of A, B, A u B, A n B, A - B and B - A. */
typedef struct {
    double a, b, a_union_b, a_inter_b, a_minus_b, b_minus_a;
} cb_cardan_volumes;

/* Number of scenarios; they are numbered 0 .. count - 1. */
int cb_cardan_scenario_count(void);

/* Scenario k (analytic faces; set a.as_nurbs, b.as_nurbs to taste), or by name (NULL name or
 * an unknown one: CB_ERR_INVALID listing the names). The scenarios, with the default shapes:
 *   cross_in_yoke      the yoke, and the cross centred on the bore axis (0, 0, hb) with its x
 *                      arms through both bores: coincident cylinders, A n B empty;
 *   cross_on_base      the cross at (0, 3.5, t + r), its -y arm lying on the base's top plane
 *                      between the yoke arms: a cylinder tangent to a plane along a line;
 *   cross_into_base    the same cross lowered by 1/4: the arm cuts into the base;
 *   cross_through_yoke the cross on the bore axis turned 60 degrees about x, its -y arm
 *                      entering the base obliquely and its x arms still coaxial in the bores;
 *   two_crosses        two crosses at the origin, B turned 45 degrees about z;
 *   crosses_stacked    B raised by 2 r along z: the x and y arms touch along lines (parallel
 *                      cylinders tangent), the +-x and +-y cube faces overlap coplanar. */
cb_status cb_cardan_scenario_get(cb_cardan_scenario *s, int k, cb_error *err);
cb_status cb_cardan_scenario_find(cb_cardan_scenario *s, const char *name, cb_error *err);

/* The volumes of a scenario from closed forms in its parts' shape parameters, not from any
 * Boolean or mesh (derivations in models/README.md); valid only for the shapes the scenario
 * was derived for: CB_ERR_INVALID when s's parts differ from cb_cardan_scenario_get's in
 * anything but as_nurbs and tol (or s->name is unknown). */
cb_status cb_cardan_scenario_volumes(cb_cardan_volumes *v, const cb_cardan_scenario *s,
                                     cb_error *err);

/* The reference table models/reference.json holds, as JSON text: the default Cardan parts with
 * their counts and volumes, every Cardan scenario with its poses, closed form and the six
 * volumes of cb_cardan_scenario_volumes; the bracket and its scenarios (B's cylinder and the
 * six volumes); the two hummingbirds (B's translation and cb_hummingbird_pair_reference); to
 * 17 significant digits. *out is a NUL-terminated string the
 * caller releases with free(); CB_ERR_NOMEM leaves it NULL. */
cb_status cb_cardan_reference_json(char **out, cb_error *err);

/* ---------------------------------------------------------------- bracket ------------------ */

/* An L-shaped bracket, in its own frame: the profile [0, L] x [0, t] (horizontal leg) and
 * [0, t] x [0, H] (vertical leg) in (x, z), its inner corner (t, t) rounded by a concave
 * quarter-circle fillet of radius f (a tangent blend: the planes x = t and z = t meet it
 * tangentially), extruded over y in [-w/2, w/2]; a hole of radius r through the vertical leg
 * along x at height hole_z, and one through the horizontal leg along z at hole_x (both at
 * y = 0). 11 faces (6 planar sides, 4 of them pierced by a hole as an inner loop; the fillet;
 * 2 L-shaped ends; 2 hole cylinders facing their axes), 27 edges, 18 vertices, exactly
 * constructible, so its volume has a closed form (cb_bracket_volume). Faces analytic or exact
 * rational B-splines (as_nurbs), pose as the Cardan parts'. */
typedef struct {
    double length, height, thickness, width; /* L, H, t, w */
    double fillet;                            /* f > 0 */
    double hole_radius, hole_x, hole_z;       /* r and the holes' positions */
} cb_bracket_shape;

typedef struct {
    cb_bracket_shape shape;
    cb_model_pose pose;
    int as_nurbs;
    double tol; /* <= 0: CB_CARDAN_REL_TOL times the largest extent */
} cb_bracket_params;

/* L = 4, H = 3, t = 1/2, w = 2, f = 1/2, r = 0.3, hole_x = 2.5, hole_z = 2; no pose. */
void cb_bracket_params_default(cb_bracket_params *p);

/* w (L t + (H - t) t + (1 - pi/4) f^2) - 2 pi r^2 t. */
double cb_bracket_volume(const cb_bracket_shape *s);

/* Builds the bracket. CB_ERR_INVALID naming the conditions when the shape is out of range
 * (0 < t < L, H; w > 0; f > 0, t + f < L, H; 0 < r < w/2; each hole clear of the fillet and of
 * its leg's end), CB_ERR_NOMEM. */
cb_status cb_model_bracket(cb_topo_body **out, const cb_bracket_params *p, cb_error *err);

/* The solid cylinder B of bracket scenario k (0: bracket_bolt, 1: bracket_rod), in the
 * bracket's frame (default shape): the circle at origin with unit axis and the seam towards
 * ref, radius, length. It only touches the bracket: V(A n B) = 0. */
typedef struct {
    double origin[3], axis[3], ref[3];
    double radius, length;
} cb_bracket_cylinder;

int cb_bracket_scenario_count(void);
/* Fills c for scenario k in 0 .. count - 1 and returns its name. */
const char *cb_bracket_scenario_cylinder(cb_bracket_cylinder *c, int k);
double cb_bracket_cylinder_volume(const cb_bracket_cylinder *c);

/* ---------------------------------------------------------------- scenarios ---------------- */

/* Error bars of the closed-form references (absolute): this fraction of the reference plus
 * CB_SCENARIO_ABS_BAR of V(A) + V(B) (so that an empty result has a bar too). */
#define CB_SCENARIO_REL_BAR 1e-6
#define CB_SCENARIO_ABS_BAR 1e-9

/* A shipped Boolean scenario loaded: its two operands (indexed, a pcurve on every coedge) and
 * the reference volumes of A u B, A n B and A - B with their absolute error bars. */
typedef struct {
    char name[64];
    cb_topo_body *a, *b;
    double ref[3], bar[3]; /* union, intersection, difference */
    const char *source;    /* where the references come from */
} cb_model_scenario;

/* The scenarios, numbered 0 .. count - 1: 0 the two hummingbirds (cb_hummingbird_pair;
 * references: V(A), V(B) by brep/mass.h and V(A n B) from cb_hummingbird_pair_reference, bars
 * three of its standard deviations), then the Cardan scenarios with analytic faces, then the
 * same with B-spline faces (names with "_nurbs"; closed forms of cb_cardan_scenario_volumes). */
int cb_model_scenario_count(void);

/* The name of scenario k (at most 63 characters). CB_ERR_INVALID for k out of range. */
cb_status cb_model_scenario_name(char *name, size_t n, int k, cb_error *err);

/* Builds scenario k into s (replaced; release with cb_model_scenario_clear). Errors of the
 * generators, CB_ERR_INVALID for k out of range. */
cb_status cb_model_scenario_load(cb_model_scenario *s, int k, cb_error *err);
void cb_model_scenario_clear(cb_model_scenario *s);

#endif
