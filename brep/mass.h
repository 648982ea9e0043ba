/* mass.h — exact mass properties of B-rep bodies: enclosed volume, boundary area and centroid,
 * by the divergence theorem over the trimmed faces, independent of any mesh.
 *
 * Method. Over a closed shell, V = (1/3) sum over faces of the integral of (x - c) . n dA and
 * the first moment M = integral of (x - c) dV = (1/4) sum of the integrals of
 * (x - c) ((x - c) . n) dA, c a reference point (the centre of the body's edge box, which keeps
 * the digits). On a face with surface S(u, v) over its trimmed domain D, n dA = e S_u x S_v
 * du dv (e = +1 when the face's same_sense is 1, else -1), and each integral over D of an
 * integrand f is turned by Green's theorem into integrals along the face's loops in (u, v):
 *   integral over D of f = e times the loop integral of F dv, F(u, v) = integral from u_ref
 *   to u of f(s, v) ds (the face's loops run counter-clockwise in (u, v) when same_sense is 1,
 *   clockwise otherwise),
 * or, on a face whose loops wind around the u period of its surface (a cylinder bounded by two
 * circles), the loop integral of -G du with G(u, v) = integral from v_ref to v of f(u, t) dt,
 * which is periodic in u, so the loops need no closing; an odd number of such loops closes at a
 * pole (a spherical cap), where v_ref is put so that G vanishes on the pole line. On a surface
 * with a pole at both ends in v (a sphere) such a face is integrated as F dv instead, each
 * loop around u closed through the closing pole along v (from its end to the pole, and from
 * the pole to its start): a pcurve passes over the other pole as a jump in u along the pole
 * line, to which F dv gives nothing but -G du the integral from pole to pole (a hemisphere
 * bounded by a great circle through both poles: trj5_s1-ac-214.stp). The
 * directions swap for loops around the v period. Faces whose loops wind around both periods (a
 * torus in one face) are not handled (CB_ERR_UNSUPPORTED). On a surface closed in u with a pole
 * at both ends in v (a sphere), a loop that does not wind bounds two regions and its sense
 * alone says which is the face: where the loops as lifted come out with a negative area (two
 * meridians, or a great circle through both poles, whose pcurves cross the pole lines at other
 * values of u), the face is the complement, and the integral over the whole band between the
 * poles (along its two sides) is added.
 * The inner integral is adaptive Gauss-Kronrod (7-15 points), split at the knots of B-spline
 * surfaces; the outer one runs over each coedge's pcurve (cb_topo_coedge_pcurve_range), adaptive
 * Gauss-Kronrod split at the knots of the pcurve and of the edge and at the knot lines of the
 * surface it crosses. Pcurves are fitted curves, so every boundary node is moved onto the true
 * edge: Newton steps from the pcurve's (u, v) to S(u, v) = C(t), C the edge curve at the node's
 * edge parameter t (the pcurve parameter when the pcurve follows the convention of brep/topo.h,
 * else the projection of S(pcurve) onto the edge, whose derivative is carried exactly), and
 * d(u, v)/dt is the derivative of that foot point, (J^T J + H) d(u, v)/dt = J^T C'(t) with
 * J = [S_u S_v] and H_ij = (S - C).S_ij (the pcurve's derivative where the Jacobian is singular,
 * at a pole). H matters where the edge lies off the surface: without it the derivative is off
 * by the gap times the curvature, and the loop integral no longer bounds the region the nodes
 * enclose (trj5_k1-al-214.stp: 1.5e-5 of one face's area for a gap of 1e-4 cm). The joints
 * between consecutive coedges (pole lines, round-off) are integrated as straight segments in
 * (u, v), so each loop is closed exactly. The result thus
 * depends on the surfaces and edge curves alone, not on how well the pcurves were fitted.
 *
 * Accuracy: each integral is refined until the Kronrod-Gauss difference is below rel_tol times the
 * integral of the integrand's magnitude (|f| inside; |F| |d(u, v)/ds| along the loops, so that a
 * loop integral of F dv along a line v = const, which is round-off, asks nothing), plus 1e-6
 * rel_tol times the body's size to the integrand's dimension; the inner integrals are asked 100
 * times finer than the outer ones. The outer integrals are also split where a coedge crosses a
 * knot line of a B-spline surface (found by sampling the coedge and bisecting), as the inner
 * integral has a kink there. This keeps the relative error of the results near rel_tol for shells
 * whose faces do not cancel each other out. Bounds on the work: an interval stops being bisected
 * when its error estimate is within the noise of the integrand's values, at depth 30, or after
 * 4000 bisections per integral; the result is then returned as it stands, without a warning.
 * A face whose inner integrals together take more than 6e6 bisections (about 30 s; an
 * ellipsoid cap's face of the Boolean corpus takes 3.1e6) fails with CB_ERR_NUMERIC naming it.
 *
 * Faces run in parallel (cb_parallel_for, ctx->threads) and are summed in face order, so the
 * results are bit-identical for any thread count. Progress is the fraction of faces done
 * (stage "mass properties"); a cancel (cb_context_cancel) returns CB_ERR_CANCELLED. */
#ifndef CB_MASS_H
#define CB_MASS_H

#include "brep/context.h"
#include "brep/topo.h"

/* Default relative accuracy. */
#define CB_MASS_REL_TOL 1e-10

typedef struct {
    double volume;      /* signed: > 0 for a shell oriented outward, < 0 for a void's shell */
    double area;        /* area of the faces */
    double centroid[3]; /* centroid of the enclosed volume (the reference point if volume 0) */
    double moment[3];   /* first moment: the integral of x dV (world origin) */
    double vector_area[3]; /* the integral of the outward normal over the faces: zero for a
                              closed surface, up to the gaps its edge tolerances allow. The
                              volume about a reference point moved by d changes by
                              -d . vector_area / 3, so a larger value says a face was integrated
                              over the wrong region and the volume is not to be trusted. */
} cb_mass_props;

/* Mass properties of shell k of body b; rel_tol <= 0 selects CB_MASS_REL_TOL. Preconditions,
 * each reported as CB_ERR_INVALID naming what failed: the incidence index built
 * (cb_topo_body_index); the shell closed (every edge of its faces used by exactly two of its
 * coedges); a pcurve on every coedge (cb_topo_compute_pcurves); every loop closed in (u, v)
 * modulo the surface's periods and pole lines. CB_ERR_UNSUPPORTED for a face with loops
 * around both periods of its surface, CB_ERR_CANCELLED, CB_ERR_NOMEM. */
cb_status cb_mass_shell(cb_mass_props *m, const cb_topo_body *b, int k, double rel_tol,
                        cb_context *ctx, cb_error *err);

/* The same for the whole body: every shell (voids count negative, as their shells face into
 * the cavity), areas added, centroid of the total volume. An open shell of a surface model
 * (a sheet beside the solids: shell.solid < 0, some edge used once) adds its area only, as it
 * bounds no volume; a body with no closed shell fails as cb_mass_shell does on the first. */
cb_status cb_mass_body(cb_mass_props *m, const cb_topo_body *b, double rel_tol, cb_context *ctx,
                       cb_error *err);

/* The area of every face of every shell of body b, open or closed (rel_tol as above): what a
 * surface model (shells that bound no volume, which cb_mass_body refuses) has of mass
 * properties. Preconditions and errors those of cb_mass_shell but the closedness; and per
 * shell the check Stokes' theorem gives (the vector area of its faces is half the integral of
 * x x dx round its free edges, those used once, each the way its coedge runs; zero for a
 * closed shell), within twice the edges' tolerances times their length plus 1e-9 of the area:
 * CB_ERR_NUMERIC, naming the shell, where a face was integrated over the wrong region of its
 * surface. *area is 0 on error. */
cb_status cb_mass_area(double *area, const cb_topo_body *b, double rel_tol, cb_context *ctx,
                       cb_error *err);

/* The largest vector area (cb_mass_props.vector_area) body b's closed shells may leave: each
 * edge's two faces meet within the edge's tolerance of it, so twice the tolerance times the
 * edges' length, plus 1e-9 of the area for rounding. The tolerance is b->tol, or each edge's
 * own where larger when edge_tols is set (a file's edges whose tolerance the reader raised;
 * a Boolean result's edges carry the weld distance, far above its faces' gaps, so it is
 * checked against b->tol). More says a face was integrated over the wrong region of its
 * surface, and the volume, which then depends on the reference point, is not to be trusted. */
double cb_mass_closure_bound(const cb_topo_body *b, double area, int edge_tols);

#endif
