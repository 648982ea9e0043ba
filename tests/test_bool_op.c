/* Booleans (cb_bool_run): results checked valid and closed, volumes against closed forms and
 * against the inclusion-exclusion identities, bad operands rejected with messages. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "boolean/bool.h"
#include "brep/mass.h"
#include "brep/mesh_check.h"
#include "brep/prim.h"
#include "brep/tess.h"
#include "check.h"
#include "io/step.h"
#include "io/step_write.h"
#include "models/models.h"
#include "revolved.h"

#define PI 3.14159265358979323846

static cb_topo_body *box(const double lo[3], const double hi[3], int as_nurbs)
{
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = cb_prim_box(&b, NULL, lo, hi, as_nurbs, 0, &err);
    CHECK(st == CB_OK, "box: %s", err.msg);
    return b;
}

static cb_topo_body *sphere(const double c[3], double r, int as_nurbs)
{
    cb_frame f;
    cb_error err;
    double z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    cb_topo_body *b = NULL;
    cb_status st = cb_frame_make(&f, c, z, x, &err);
    if (!st)
        st = cb_prim_sphere(&b, &f, r, as_nurbs, 0, &err);
    CHECK(st == CB_OK, "sphere: %s", err.msg);
    return b;
}

/* Vertices where the exact result is not a manifold (two parts touching at points): the next
 * check_op expects exactly this many in the mesh, then it is 0 again. */
static int touching_points;
/* The next check_op's result touches itself along a curve or at a point with no vertex in
 * common (the union of solids touching along a line, or a sphere on a plane): its mesh must be
 * reported as self-intersecting, where the two sides touch. */
static int touching_curve;
/* The next check_op's result has a void touching the outer wall (at a point, or along a
 * curve) where the meshes of the two need not meet: its mesh may touch itself there, but no
 * two triangles may cross. */
static int void_contact;
/* The next check_op also writes its result as STEP, reads it back and checks it again: valid,
 * the same volume within 1e-9. */
static int write_back;
/* The next check_op does not mesh its result (a case whose tessellation is known to fail,
 * said where it is set). */
static int no_mesh;

/* Runs op and checks the result: valid, its B-rep volume within rel of expected, and its mesh
 * (default tolerances) closed, manifold and free of self-intersections by CGAL (with
 * touching_points non-manifold vertices: CGAL's checks cannot run there). Where the result
 * touches itself (touching_points, touching_curve), the triangles that meet there must touch,
 * none cross (cb_mesh_check_contacts at the result's tolerance). */
static void check_op(const char *name, cb_bool_op op, const cb_topo_body *A, const cb_topo_body *B,
                     double expected, double rel, double *volume)
{
    int touching = touching_points, touching_line = touching_curve, back = write_back;
    int mesh_it = !no_mesh, in_void = void_contact;
    touching_points = touching_curve = write_back = no_mesh = void_contact = 0;
    cb_topo_body *res = NULL;
    cb_bool_stats stats;
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_bool_run(&res, &stats, op, A, B, NULL, NULL, &err);
    CHECK(st == CB_OK && res, "%s %s: %s", name, cb_bool_op_name(op), err.msg);
    if (st)
        return;
    cb_topo_report r;
    cb_topo_report_init(&r);
    st = cb_topo_validate(&r, res, res->tol, 9, &err);
    CHECK(st == CB_OK && r.n == 0, "%s %s: result not valid: %s (%d problems)", name,
          cb_bool_op_name(op), st ? err.msg : r.n ? r.items[0] : "", r.n);
    cb_topo_report_clear(&r);
    cb_mass_props m;
    st = cb_mass_body(&m, res, 1e-10, NULL, &err);
    int mass_ok = st == CB_OK;
    CHECK(st == CB_OK, "%s %s: volume: %s", name, cb_bool_op_name(op), err.msg);
    if (!st) {
        double e = expected != 0 ? fabs(m.volume - expected) / fabs(expected) : fabs(m.volume);
        if (expected >= 0)
            CHECK(e <= rel, "%s %s: volume %.12g, expected %.12g (rel %.3g)", name,
                  cb_bool_op_name(op), m.volume, expected, e);
        printf("%-22s %-12s %2d curves %2d cuts, faces %3d, volume %.12g (rel %.2e), %.2f s\n",
               name, cb_bool_op_name(op), stats.curves, stats.cuts, res->n_faces, m.volume, e,
               stats.time_ssi + stats.time_split + stats.time_build);
        if (volume)
            *volume = m.volume;
    }
    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    cb_mesh_check_report cr;
    st = res->n_faces && mesh_it ? cb_tess_body(mesh, res, NULL, NULL, &err) : CB_OK;
    if (!st && res->n_faces && mesh_it)
        st = cb_mesh_check(&cr, mesh, &err);
    CHECK(st == CB_OK, "%s %s: mesh: %s", name, cb_bool_op_name(op), err.msg);
    if (!st && res->n_faces && mesh_it)
        CHECK(cr.closed && cr.edge_manifold &&
                  (in_void || cr.nonmanifold_vertices == touching) &&
                  cr.oriented &&
                  (touching || in_void ||
                   cr.self_intersections == (touching_line ? 1 : 0)),
              "%s %s: mesh of %d triangles: %d boundary, %d non-manifold edges, %d non-manifold "
              "vertices, %d misoriented edges, self-intersections %d",
              name, cb_bool_op_name(op), cr.triangles, cr.boundary_edges, cr.nonmanifold_edges,
              cr.nonmanifold_vertices, cr.misoriented_edges, cr.self_intersections);
    if (!st && res->n_faces && mesh_it && (touching || touching_line || in_void)) {
        cb_mesh_contacts c;
        st = cb_mesh_check_contacts(&c, mesh, res->tol, &err);
        CHECK(st == CB_OK && (c.touching > 0 || in_void) && c.crossing == 0,
              "%s %s: where the mesh meets itself: %d pairs of triangles touching, %d crossing "
              "(%s)",
              name, cb_bool_op_name(op), c.touching, c.crossing, st ? err.msg : "");
    }
    cb_mesh_clear(mesh);
    if (back && mass_ok && res->n_faces) {
        char path[1024];
        const char *tmp = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
        snprintf(path, sizeof path, "%s/colibri_bool_op_%d.step", tmp, (int)getpid());
        cb_topo_body *c = NULL;
        st = cb_step_write(res, path, "result", &err);
        if (!st)
            st = cb_step_read(&c, path, &err);
        CHECK(st == CB_OK, "%s %s: written back: %s", name, cb_bool_op_name(op), err.msg);
        if (!st) {
            cb_topo_report_init(&r);
            cb_status vs = cb_topo_validate(&r, c, 0, 9, &err);
            CHECK(vs == CB_OK && r.n == 0, "%s %s: read back not valid: %s", name,
                  cb_bool_op_name(op), vs ? err.msg : r.n ? r.items[0] : "");
            cb_topo_report_clear(&r);
            cb_mass_props m2;
            vs = cb_mass_body(&m2, c, 1e-10, NULL, &err);
            CHECK(vs == CB_OK && fabs(m2.volume - m.volume) <= 1e-9 * fabs(m.volume),
                  "%s %s: read back: volume %.12g, %.12g before (%s)", name, cb_bool_op_name(op),
                  vs ? NAN : m2.volume, m.volume, vs ? err.msg : "");
            cb_mesh_t m3;
            cb_mesh_init(m3);
            vs = cb_tess_body(m3, c, NULL, NULL, &err);
            if (!vs)
                vs = cb_mesh_check(&cr, m3, &err);
            CHECK(vs == CB_OK && cr.closed && cr.edge_manifold && cr.oriented,
                  "%s %s: read back: mesh: %s (closed %d, edge-manifold %d, oriented %d)", name,
                  cb_bool_op_name(op), vs ? err.msg : "", vs ? -1 : cr.closed,
                  vs ? -1 : cr.edge_manifold, vs ? -1 : cr.oriented);
            cb_mesh_clear(m3);
        }
        cb_topo_body_free(c);
        remove(path);
    }
    cb_topo_body_free(res);
}

/* A sphere of radius 1/2 centred on the top face of the box [0, 2]^3: half of it inside. */
static void test_sphere_on_face(int as_nurbs)
{
    double lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2}, c[3] = {1, 1, 2}, r = 0.5;
    cb_topo_body *A = box(lo, hi, 1), *B = sphere(c, r, as_nurbs);
    if (A && B) {
        double half = 2.0 / 3 * PI * r * r * r;
        const char *name = as_nurbs ? "box, NURBS sphere" : "box, sphere on face";
        check_op(name, CB_BOOL_UNION, A, B, 8 + half, 1e-6, NULL);
        check_op(name, CB_BOOL_INTERSECTION, A, B, half, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, A, B, 8 - half, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, B, A, half, 1e-6, NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* A unit sphere centred on a corner of the box [0, 2]^3: an eighth inside; its cuts end on
 * the box's edges, which are split there. */
static void test_sphere_on_corner(int as_nurbs)
{
    double lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2}, c[3] = {2, 2, 2}, r = 1;
    cb_topo_body *A = box(lo, hi, 1), *B = sphere(c, r, as_nurbs);
    if (A && B) {
        double eighth = PI / 6;
        const char *name = as_nurbs ? "box, NURBS sphere on corner" : "box, sphere on corner";
        check_op(name, CB_BOOL_UNION, A, B, 8 + 7 * eighth, 1e-6, NULL);
        check_op(name, CB_BOOL_INTERSECTION, A, B, eighth, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, A, B, 8 - eighth, 1e-6, NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

static cb_topo_body *cylinder(const double o[3], const double axis[3], const double ref[3],
                              double r, double h, int as_nurbs)
{
    cb_frame f;
    cb_error err;
    cb_topo_body *b = NULL;
    cb_status st = cb_frame_make(&f, o, axis, ref, &err);
    if (!st)
        st = cb_prim_cylinder(&b, &f, r, h, as_nurbs, 0, &err);
    CHECK(st == CB_OK, "cylinder: %s", err.msg);
    return b;
}

/* The Steinmetz bicylinder: unit cylinders of length 4 along x and y crossing at the origin;
 * their intersection curves are two ellipses crossing at (0, 0, +-1), where the surfaces
 * touch. ref: where the seams lie (z: through the crossing points, where OCCT 7.6 loses the
 * intersection). As B-splines the faces are recognised as the exact rational cylinders they
 * are (ssi/README.md: the fast path) and intersected in closed form. */
/* The three Booleans of the bicylinder A, B (unit radius, length 4, axes x and y). */
static void steinmetz_ops(const char *name, const cb_topo_body *A, const cb_topo_body *B)
{
    double vi = 16.0 / 3, vc = 4 * PI;
    check_op(name, CB_BOOL_INTERSECTION, A, B, vi, 1e-6, NULL);
    check_op(name, CB_BOOL_UNION, A, B, 2 * vc - vi, 1e-6, NULL);
    /* The cylinder less the other one: two parts touching at (0, 0, +-1). */
    touching_points = 2;
    check_op(name, CB_BOOL_DIFFERENCE, A, B, vc - vi, 1e-6, NULL);
}

static void test_steinmetz(int as_nurbs, const double ref[3], const char *name)
{
    double ox[3] = {-2, 0, 0}, x[3] = {1, 0, 0}, oy[3] = {0, -2, 0}, y[3] = {0, 1, 0};
    cb_topo_body *A = cylinder(ox, x, ref, 1, 4, as_nurbs), *B = cylinder(oy, y, ref, 1, 4, as_nurbs);
    if (A && B)
        steinmetz_ops(name, A, B);
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* Two unit spheres whose centres are 1 apart: the lens between them has volume 5 pi / 12. A
 * torus (R = 2, r = 1/2) cut by the box below its centre plane: half of it, pi^2 R r^2.
 * Analytic faces work, and B-spline ones: the torus (its cuts run along the seam of its
 * periodic patches, classified on the seam's lower copy) and the spheres (recognised as
 * spheres by the SSI, ssi_recog.c: their rounded conic weights leave the subdivision route
 * uncertified). */
static void test_lens_torus(int as_nurbs)
{
    double c1[3] = {0, 0, 0}, c2[3] = {1, 0, 0};
    cb_topo_body *A = sphere(c1, 1, as_nurbs), *B = sphere(c2, 1, as_nurbs);
    const char *name = as_nurbs ? "lens NURBS" : "lens";
    if (A && B) {
        double lens = 5 * PI / 12, ball = 4 * PI / 3;
        check_op(name, CB_BOOL_INTERSECTION, A, B, lens, 1e-6, NULL);
        check_op(name, CB_BOOL_UNION, A, B, 2 * ball - lens, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, A, B, ball - lens, 1e-6, NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
    cb_frame f;
    cb_error err;
    double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    cb_topo_body *T = NULL, *X = NULL;
    double lo[3] = {-3, -3, -1}, hi[3] = {3, 3, 0};
    cb_status st = cb_frame_make(&f, o, z, x, &err);
    if (!st)
        st = cb_prim_torus(&T, &f, 2, 0.5, as_nurbs, 0, &err);
    if (!st)
        st = cb_prim_box(&X, NULL, lo, hi, as_nurbs, 0, &err);
    CHECK(st == CB_OK, "torus, box: %s", err.msg);
    if (!st) {
        double half = PI * PI * 2 * 0.25, box = 36;
        name = as_nurbs ? "torus and box NURBS" : "torus and box";
        check_op(name, CB_BOOL_INTERSECTION, T, X, half, 1e-6, NULL);
        check_op(name, CB_BOOL_UNION, T, X, box + half, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, T, X, half, 1e-6, NULL);
    }
    cb_topo_body_free(T);
    cb_topo_body_free(X);
}

/* Faces of revolution and extrusion (issue 22): primitives whose curved faces are rewritten as
 * revolutions of circles and lines, or extrusions of circles (tests/revolved.h: the same
 * parameterisation, so edges and pcurves stay), in Booleans with closed-form volumes: a sphere
 * on a box face, a torus cut by a box below its centre plane (half of it), the Steinmetz
 * bicylinder (a revolved cylinder against an extruded one), and a second operation on a
 * result whose revolution face spans part of a turn (the cylinder r = 1 cut by the plane
 * x = 0.3: angles +-acos 0.3, not whole quarters, so the B-spline form has rounded weights),
 * cut again by two planes. */
static void test_revolved(void)
{
    cb_error err;
    double lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2}, c[3] = {1, 1, 2}, r = 0.5;
    cb_topo_body *A = box(lo, hi, 0), *B = sphere(c, r, 0);
    if (A && B && test_revolve_surfaces(B, 0) == 1) {
        double half = 2.0 / 3 * PI * r * r * r;
        const char *name = "box, revolved sphere";
        check_op(name, CB_BOOL_UNION, A, B, 8 + half, 1e-6, NULL);
        check_op(name, CB_BOOL_INTERSECTION, A, B, half, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, A, B, 8 - half, 1e-6, NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);

    cb_frame f;
    double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    cb_topo_body *T = NULL, *X = NULL;
    double tlo[3] = {-3, -3, -1}, thi[3] = {3, 3, 0};
    cb_status st = cb_frame_make(&f, o, z, x, &err);
    if (!st)
        st = cb_prim_torus(&T, &f, 2, 0.5, 0, 0, &err);
    if (!st)
        st = cb_prim_box(&X, NULL, tlo, thi, 0, 0, &err);
    CHECK(st == CB_OK, "torus, box: %s", err.msg);
    if (!st && test_revolve_surfaces(T, 0) == 2) {
        double half = PI * PI * 2 * 0.25, vbox = 36;
        const char *name = "revolved torus and box";
        check_op(name, CB_BOOL_INTERSECTION, T, X, half, 1e-6, NULL);
        check_op(name, CB_BOOL_UNION, T, X, vbox + half, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, T, X, half, 1e-6, NULL);
    }
    cb_topo_body_free(T);
    cb_topo_body_free(X);

    double ox[3] = {-2, 0, 0}, ax[3] = {1, 0, 0}, oy[3] = {0, -2, 0}, ay[3] = {0, 1, 0};
    double ref[3] = {0, 0.6, 0.8};
    A = cylinder(ox, ax, ref, 1, 4, 0);
    B = cylinder(oy, ay, ref, 1, 4, 0);
    if (A && B && test_revolve_surfaces(A, 0) == 1 && test_revolve_surfaces(B, 1) == 1)
        steinmetz_ops("steinmetz revolved/extruded", A, B);
    cb_topo_body_free(A);
    cb_topo_body_free(B);

    double slo[3] = {0.3, -2, -1}, shi[3] = {2, 2, 3}, plo[3] = {-2, -2, 0.5}, phi[3] = {2, 2, 1.2};
    A = cylinder(o, z, x, 1, 2, 0);
    B = box(slo, shi, 0);
    cb_topo_body *P = box(plo, phi, 0), *S = NULL;
    double seg = acos(0.3) - 0.3 * sqrt(0.91); /* area of the disc's part beyond x = 0.3 */
    if (A && B && P && test_revolve_surfaces(A, 0) == 1) {
        cb_bool_stats stats;
        cb_error_clear(&err);
        st = cb_bool_run(&S, &stats, CB_BOOL_INTERSECTION, A, B, NULL, NULL, &err);
        CHECK(st == CB_OK && S, "revolved cylinder segment: %s", err.msg);
        /* the side keeps its surface of revolution (one face or two, split at the seam) */
        int partial = 0;
        for (int k = 0; S && k < S->n_faces; k++)
            partial += S->surfaces[S->faces[k].surface].kind == CB_SURFACE_REVOLUTION;
        CHECK(partial >= 1, "revolved cylinder segment: no face of revolution");
        if (S) {
            const char *name = "revolved segment, slab";
            check_op(name, CB_BOOL_INTERSECTION, S, P, 0.7 * seg, 1e-6, NULL);
            check_op(name, CB_BOOL_DIFFERENCE, S, P, 1.3 * seg, 1e-6, NULL);
        }
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
    cb_topo_body_free(P);
    cb_topo_body_free(S);
}

/* Why result res is not acceptable (invalid, no volume, or a mesh that is not a closed,
 * manifold surface free of self-intersections), or NULL when it is. */
static const char *flaw(cb_topo_body *res, cb_error *err)
{
    cb_topo_report r;
    cb_topo_report_init(&r);
    cb_status st = cb_topo_validate(&r, res, res->tol, 9, err);
    int bad = st || r.n;
    cb_topo_report_clear(&r);
    if (bad)
        return "result not valid";
    cb_mass_props m;
    if (cb_mass_body(&m, res, 1e-10, NULL, err))
        return "volume integration fails";
    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    cb_mesh_check_report cr;
    st = cb_tess_body(mesh, res, NULL, NULL, err);
    if (!st)
        st = cb_mesh_check(&cr, mesh, err);
    cb_mesh_clear(mesh);
    if (st)
        return "no mesh";
    if (!cr.closed || !cr.edge_manifold || !cr.vertex_manifold || cr.self_intersections)
        return "mesh not a closed manifold free of self-intersections";
    return NULL;
}

/* The Cardan scenarios (models/README.md), analytic or exact rational B-spline faces, volumes
 * from their closed forms. ops: which of union, intersection, A - B, B - A are expected to
 * give a result (bits 0..3); the others, known gaps, must fail with a message or give a result
 * that a check rejects, never one that passes as right. The scenarios
 * cover a cylinder cut into a plane, coincident planes (two crosses: the cubes' top and
 * bottom), coincident cylinders (the cross's arms in the yoke's bores), a cylinder lying on a
 * plane along a line. */
static void test_cardan_scenario(const char *scenario, int as_nurbs, unsigned ops)
{
    cb_cardan_scenario sc;
    cb_cardan_volumes v;
    cb_error err;
    cb_topo_body *A = NULL, *B = NULL;
    cb_status st = cb_cardan_scenario_find(&sc, scenario, &err);
    sc.a.as_nurbs = sc.b.as_nurbs = as_nurbs;
    if (!st)
        st = cb_cardan_scenario_volumes(&v, &sc, &err);
    if (!st)
        st = cb_model_cardan(&A, &sc.a, &err);
    if (!st)
        st = cb_model_cardan(&B, &sc.b, &err);
    CHECK(st == CB_OK, "cardan %s: %s", scenario, err.msg);
    if (!st) {
        char name[64];
        snprintf(name, sizeof name, "%s%s", scenario, as_nurbs ? " NURBS" : "");
        const cb_bool_op op[4] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE,
                                  CB_BOOL_DIFFERENCE};
        const double want[4] = {v.a_union_b, v.a_inter_b, v.a_minus_b, v.b_minus_a};
        for (int k = 0; k < 4; k++) {
            const cb_topo_body *X = k == 3 ? B : A, *Y = k == 3 ? A : B;
            if (ops >> k & 1) {
                check_op(name, op[k], X, Y, want[k], 1e-6, NULL);
            } else {
                cb_topo_body *res = NULL;
                st = cb_bool_run(&res, NULL, op[k], X, Y, NULL, NULL, &err);
                const char *why = st ? err.msg : flaw(res, &err);
                CHECK(why != NULL, "%s %s%s: a result that passes every check, where a known gap "
                      "was expected (move it to the handled operations)",
                      name, cb_bool_op_name(op[k]), k == 3 ? " (B - A)" : "");
                if (why)
                    printf("%-22s %-12s %s: %s\n", name, cb_bool_op_name(op[k]),
                           st ? "refused" : "flagged", why);
                cb_topo_body_free(res);
            }
        }
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* The default cross of p's shape (analytic or B-spline faces) as A, and B the same cross
 * moved by t; the volume of one cross in *cross (8 a^3 + 4 pi r^2 (L - a)). */
static cb_status cross_and_moved(cb_topo_body **A, cb_topo_body **B, double *cross,
                                 const cb_cardan_params *p, const double t[3], cb_error *err)
{
    cb_cardan_params q = *p;
    const double r = q.cross.arm_radius, a = q.cross.half_size, L = q.cross.arm_reach;
    *cross = 8 * a * a * a + 4 * PI * r * r * (L - a);
    cb_status st = cb_model_cardan(A, &q, err);
    for (int k = 0; k < 3; k++)
        q.pose.translate[k] = t[k];
    if (!st)
        st = cb_model_cardan(B, &q, err);
    return st;
}

/* Two crosses side by side, B moved by (a, a, 0) (a = 1): the cubes share the quarter
 * [0, a]^2 x [-a, a]; each cube holds half of one arm of the other over a length a (A's +x
 * and +y arms, B's -x and -y arms: 4 half discs, pi r^2 / 2 each); A's +x arm meets B's -y arm, and A's +y
 * arm B's -x arm, beside the cubes in a quarter of a Steinmetz bicylinder (4 r^3 / 3 each). The
 * arms' boundary lines z = +-r on the cube faces are tangent to the other arm's circle there.
 * A - B is three solids touching at points: A's +x and +y arms come off where B's arms cut
 * through them. */
static void test_crosses_side(int as_nurbs)
{
    cb_cardan_params p;
    cb_cardan_params_default(&p, CB_CARDAN_CROSS);
    p.as_nurbs = as_nurbs;
    const double r = p.cross.arm_radius, a = p.cross.half_size, t[3] = {a, a, 0};
    cb_topo_body *A = NULL, *B = NULL;
    cb_error err;
    double cross;
    cb_status st = cross_and_moved(&A, &B, &cross, &p, t, &err);
    CHECK(st == CB_OK, "crosses side by side: %s", err.msg);
    if (!st) {
        double inter = 2 * a * a * a + 4 * (PI * r * r / 2) * a + 2 * (4 * r * r * r / 3);
        const char *name = as_nurbs ? "crosses side by side NURBS" : "crosses side by side";
        check_op(name, CB_BOOL_UNION, A, B, 2 * cross - inter, 1e-6, NULL);
        check_op(name, CB_BOOL_INTERSECTION, A, B, inter, 1e-6, NULL);
        /* A known gap: the difference's volume is right, but where the arms' remnants touch
         * the body at points its B-rep joins them by tiny edges (tangent curves merged over
         * a window in the face's arrangement), which the mesh shows as non-manifold edges. */
        cb_topo_body *res = NULL;
        st = cb_bool_run(&res, NULL, CB_BOOL_DIFFERENCE, A, B, NULL, NULL, &err);
        const char *why = st ? err.msg : flaw(res, &err);
        CHECK(why != NULL, "%s difference: passes every check now; make it a handled case",
              name);
        printf("%-22s %-12s flagged: %s\n", name, "difference", why ? why : "-");
        cb_topo_body_free(res);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* The stacked crosses shifted by a / 2 along x (B moved by (a/2, 0, 2r), a = 1, r = 3/8):
 * the cubes share [-a/2, a] x [-a, a] x [2r - a, a]; A's +x arm runs a/2 into B's cube and
 * B's -x arm a/2 into A's, each cut by the other cube's face at distance a - 2r from its
 * axis (a disc less the segment beyond a chord at that distance); the x arms are tangent
 * along lines, the y arms miss each other. On A's cube face x = -a the circle where B's -x
 * arm passes through touches A's arm hole: the face's one loop visits that contact twice, and
 * with B-spline faces the two visits' (u, v) differ by round-off (the triangulation stalled
 * until such copies were unified). */
static void test_crosses_shifted(int as_nurbs)
{
    cb_cardan_params p;
    cb_cardan_params_default(&p, CB_CARDAN_CROSS);
    p.as_nurbs = as_nurbs;
    const double r = p.cross.arm_radius, a = p.cross.half_size, t[3] = {a / 2, 0, 2 * r};
    cb_topo_body *A = NULL, *B = NULL;
    cb_error err;
    double cross;
    cb_status st = cross_and_moved(&A, &B, &cross, &p, t, &err);
    CHECK(st == CB_OK, "crosses shifted: %s", err.msg);
    if (!st) {
        double d = a - 2 * r, seg = r * r * acos(d / r) - d * sqrt(r * r - d * d);
        double inter =
            (1.5 * a) * (2 * a) * (2 * a - 2 * r) + 2 * (PI * r * r - seg) * (a / 2);
        const char *name = as_nurbs ? "crosses shifted NURBS" : "crosses shifted";
        check_op(name, CB_BOOL_UNION, A, B, 2 * cross - inter, 1e-6, NULL);
        check_op(name, CB_BOOL_INTERSECTION, A, B, inter, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, A, B, cross - inter, 1e-6, NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

static void test_cardan(int as_nurbs)
{
    test_cardan_scenario("cross_into_base", as_nurbs, 0xf);
    test_cardan_scenario("two_crosses", as_nurbs, 0xf);
    test_cardan_scenario("cross_in_yoke", as_nurbs, 0xf);
    test_cardan_scenario("cross_through_yoke", as_nurbs, 0xf);
    /* Arms tangent along lines, arm circles touching at points on coplanar faces: the union
     * touches itself along the four lines, whose far ends, where the arms' end caps touch, are
     * non-manifold vertices of the mesh. */
    touching_points = 4;
    test_cardan_scenario("crosses_stacked", as_nurbs, 0xf);
    /* The cylinder lying on the plane: A u B touches itself along the line. */
    touching_curve = 1;
    test_cardan_scenario("cross_on_base", as_nurbs, 0xf);
}

static void test_determinism(const cb_topo_body *A, const cb_topo_body *B);

/* Two hummingbirds with pcurves on every coedge (the Booleans need them). */
static cb_status two_birds(cb_topo_body **A, cb_topo_body **B, const cb_hummingbird_params *pa,
                           const cb_hummingbird_params *pb, cb_error *err)
{
    cb_status st = cb_model_hummingbird(A, pa, err);
    if (!st)
        st = cb_model_hummingbird(B, pb, err);
    if (!st)
        st = cb_topo_compute_pcurves(*A, (*A)->tol, err);
    if (!st)
        st = cb_topo_compute_pcurves(*B, (*B)->tol, err);
    CHECK(st == CB_OK, "hummingbird: %s", err->msg);
    return st;
}

/* Two hummingbirds, the second moved (cb_hummingbird_pair): the volumes must satisfy
 * V(A u B) + V(A n B) = V(A) + V(B) and V(A - B) = V(A) - V(A n B), and V(A n B) must agree
 * with the reference estimate (vertical lines, no Boolean code) within three of its standard
 * deviations. */
static void test_birds(void)
{
    cb_hummingbird_params pa, pb;
    cb_hummingbird_pair(&pa, &pb);
    cb_topo_body *A = NULL, *B = NULL;
    cb_error err;
    cb_status st = two_birds(&A, &B, &pa, &pb, &err);
    if (!st) {
        cb_mass_props ma, mb;
        cb_mass_body(&ma, A, 1e-10, NULL, &err);
        cb_mass_body(&mb, B, 1e-10, NULL, &err);
        const cb_overlap_estimate *ref = &cb_hummingbird_pair_reference;
        double bar = 3 * ref->sigma_ab;
        double vu = NAN, vi = NAN, vd = NAN;
        check_op("two birds", CB_BOOL_UNION, A, B, ma.volume + mb.volume - ref->volume_ab,
                 bar / (ma.volume + mb.volume - ref->volume_ab), &vu);
        check_op("two birds", CB_BOOL_INTERSECTION, A, B, ref->volume_ab, bar / ref->volume_ab,
                 &vi);
        check_op("two birds", CB_BOOL_DIFFERENCE, A, B, ma.volume - ref->volume_ab,
                 bar / (ma.volume - ref->volume_ab), &vd);
        double e1 = fabs(vu + vi - ma.volume - mb.volume) / ma.volume;
        double e2 = fabs(vd - (ma.volume - vi)) / ma.volume;
        CHECK(e1 <= 1e-6 && e2 <= 1e-6,
              "birds: V(A u B) + V(A n B) - V(A) - V(B) = %.3g, V(A - B) - V(A) + V(A n B) = "
              "%.3g (relative to V(A) = %.6g)",
              e1, e2, ma.volume);
        printf("birds: V(A n B) %.9g, reference %.9g +- %.2g (3 sigma): %.2f sigma off\n", vi,
               ref->volume_ab, bar, fabs(vi - ref->volume_ab) / ref->sigma_ab);
        test_determinism(A, B);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* The birds posed as in the paper's Fig. 12 (B turned 40 degrees about a tilted axis, wings
 * lowered to 5 degrees: bodies, wings and tails cross at shallow angles). Every operation
 * valid with a mesh that passes, V(A - B) = V(A) - V(A n B), V(A u B) = V(A) + V(B) -
 * V(A n B). (The union's mesh used to cross itself: needle triangles of the tessellation.) */
static void test_birds_fig12(void)
{
    cb_hummingbird_params pa, pb;
    cb_hummingbird_params_default(&pa);
    cb_hummingbird_params_default(&pb);
    pb.wing_angle_deg = 5;
    pb.axis[0] = 0.2;
    pb.axis[1] = 0.3;
    pb.axis[2] = 1;
    pb.angle_deg = 40;
    pb.translate[0] = 0.4;
    pb.translate[1] = 0.25;
    pb.translate[2] = 0.15;
    cb_topo_body *A = NULL, *B = NULL;
    cb_error err;
    cb_status st = two_birds(&A, &B, &pa, &pb, &err);
    if (!st) {
        cb_mass_props ma, mb;
        cb_mass_body(&ma, A, 1e-10, NULL, &err);
        cb_mass_body(&mb, B, 1e-10, NULL, &err);
        double vi = NAN, vd = NAN;
        check_op("birds, Fig. 12 pose", CB_BOOL_INTERSECTION, A, B, -1, 0, &vi);
        check_op("birds, Fig. 12 pose", CB_BOOL_DIFFERENCE, A, B, -1, 0, &vd);
        CHECK(fabs(vd - (ma.volume - vi)) <= 1e-6 * ma.volume,
              "birds, Fig. 12 pose: V(A - B) %.10g, V(A) - V(A n B) %.10g", vd, ma.volume - vi);
        check_op("birds, Fig. 12 pose", CB_BOOL_UNION, A, B, ma.volume + mb.volume - vi, 1e-6,
                 NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* Contacts, analytic and NURBS: two boxes sharing a face (whole, or in part), a sphere touching
 * a box at one point (the union: two solids touching there, whose mesh is reported
 * self-intersecting at the point), a cylinder lying on a box along a line (the union: two
 * solids touching along it, whose mesh is reported self-intersecting there), and a
 * cylinder in a hole of its own radius (coincident cylinders). Each in all three operations,
 * volumes from the closed forms. */
static void test_contacts(int as_nurbs)
{
    char name[64];
    const double x[3] = {1, 0, 0}, z[3] = {0, 0, 1}, y[3] = {0, 1, 0};
    double lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2}, lo2[3] = {2, 0, 0}, hi2[3] = {4, 2, 2};
    double lo3[3] = {2, 1, 0}, hi3[3] = {4, 3, 2}, c[3] = {1, 1, 3};
    cb_topo_body *A = box(lo, hi, as_nurbs), *B = box(lo2, hi2, as_nurbs);
    cb_topo_body *B2 = box(lo3, hi3, as_nurbs), *S = sphere(c, 1, as_nurbs);
    const double ol[3] = {-1, 1, 2.5}, op[3] = {1, 1, -1};
    cb_topo_body *L = cylinder(ol, x, z, 0.5, 4, as_nurbs), *P = cylinder(op, z, x, 0.5, 4, as_nurbs);
    cb_topo_body *Q = cylinder(op, z, y, 0.5, 4, as_nurbs), *H = NULL;
    if (A && B && B2 && S && L && P && Q) {
        const cb_topo_body *other[3] = {B, B2, S};
        const char *what[3] = {"boxes sharing a face", "boxes sharing part of one",
                               "sphere touching a box"};
        const double vb[3] = {8, 8, 4 * PI / 3};
        for (int k = 0; k < 3; k++) {
            snprintf(name, sizeof name, "%s%s", what[k], as_nurbs ? " NURBS" : "");
            touching_curve = k == 2;
            check_op(name, CB_BOOL_UNION, A, other[k], 8 + vb[k], 1e-6, NULL);
            check_op(name, CB_BOOL_INTERSECTION, A, other[k], 0, 1e-6, NULL);
            check_op(name, CB_BOOL_DIFFERENCE, A, other[k], 8, 1e-6, NULL);
        }
        snprintf(name, sizeof name, "cylinder lying on a box%s", as_nurbs ? " NURBS" : "");
        touching_curve = 1;
        check_op(name, CB_BOOL_UNION, A, L, 8 + PI, 1e-6, NULL);
        check_op(name, CB_BOOL_INTERSECTION, A, L, 0, 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, A, L, 8, 1e-6, NULL);
        /* One end on the box: the line of contact ends on that end's circle, at its lowest
         * point, between the samples a box round the circle was once made of (the seam turned
         * off the top by a generic angle). */
        const double oe[3] = {0.5, 1, 2.5}, ref[3] = {0, 0.6, 0.8};
        cb_topo_body *E = cylinder(oe, x, ref, 0.5, 3, as_nurbs);
        if (E) {
            snprintf(name, sizeof name, "cylinder with an end on a box%s",
                     as_nurbs ? " NURBS" : "");
            touching_curve = 1;
            check_op(name, CB_BOOL_UNION, A, E, 8 + 0.75 * PI, 1e-6, NULL);
            check_op(name, CB_BOOL_INTERSECTION, A, E, 0, 1e-6, NULL);
            check_op(name, CB_BOOL_DIFFERENCE, A, E, 8, 1e-6, NULL);
        }
        cb_topo_body_free(E);
        cb_error err;
        cb_status st = cb_bool_run(&H, NULL, CB_BOOL_DIFFERENCE, A, P, NULL, NULL, &err);
        CHECK(st == CB_OK, "box with a hole: %s", err.msg);
        if (!st) {
            /* Q's seam on +y, the hole's on +x: the coincident faces are cut at other places. */
            snprintf(name, sizeof name, "cylinder in its hole%s", as_nurbs ? " NURBS" : "");
            check_op(name, CB_BOOL_UNION, H, Q, 8 + PI / 2, 1e-6, NULL);
            check_op(name, CB_BOOL_INTERSECTION, H, Q, 0, 1e-6, NULL);
            check_op(name, CB_BOOL_DIFFERENCE, H, Q, 8 - PI / 2, 1e-6, NULL);
        }
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
    cb_topo_body_free(B2);
    cb_topo_body_free(S);
    cb_topo_body_free(L);
    cb_topo_body_free(P);
    cb_topo_body_free(Q);
    cb_topo_body_free(H);
}

/* Voids touching the wall of their solid: a ball inside a ball, touching it at a point, and
 * a ball inside a cylinder of its radius, touching it along a circle, both in general
 * position (the contacts on no seam or pole). A chord of the wall's mesh dips towards the
 * void by up to the chordal tolerance, and across the contact reaches past the void's mesh
 * unless the tessellation refines it there. */
static void test_voids(int as_nurbs)
{
    char name[64];
    const double o[3] = {0, 0, 0}, d[3] = {0.48, 0.36, 0.8}, r = 1.25, r2 = 0.75;
    double c[3], a[3] = {2.0 / 7, 3.0 / 7, 6.0 / 7}, ref[3] = {1, 0, 0}, oc[3] = {0.1, -0.2, 0.3};
    for (int i = 0; i < 3; i++)
        c[i] = (r - r2) * d[i];
    cb_topo_body *A = sphere(o, r, as_nurbs), *B = sphere(c, r2, as_nurbs);
    if (A && B) {
        snprintf(name, sizeof name, "ball in a ball%s", as_nurbs ? " NURBS" : "");
        void_contact = 1;
        check_op(name, CB_BOOL_DIFFERENCE, A, B, 4 * PI / 3 * (r * r * r - r2 * r2 * r2), 1e-6,
                 NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
    for (int i = 0; i < 3; i++)
        c[i] = oc[i] + 1.5 * a[i];
    A = cylinder(oc, a, ref, 1, 3, as_nurbs);
    B = sphere(c, 1, as_nurbs);
    if (A && B) {
        snprintf(name, sizeof name, "ball in a cylinder%s", as_nurbs ? " NURBS" : "");
        void_contact = 1;
        check_op(name, CB_BOOL_DIFFERENCE, A, B, 3 * PI - 4 * PI / 3, 1e-6, NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* The bracket scenarios (models/scenario.c): a bolt through the hole of the horizontal leg
 * (coincident cylinders) and a rod lying in the inner corner (coincident with the fillet, the
 * tangent blend, and tangent to the two planes along its edges), analytic and NURBS, all four
 * operations against the closed forms. */
static void test_brackets(void)
{
    int n = cb_model_scenario_count();
    for (int k = 0; k < n; k++) {
        char name[64];
        cb_error err;
        if (cb_model_scenario_name(name, sizeof name, k, &err) || strncmp(name, "bracket", 7))
            continue;
        cb_model_scenario s;
        cb_status st = cb_model_scenario_load(&s, k, &err);
        CHECK(st == CB_OK, "%s: %s", name, err.msg);
        if (st)
            continue;
        double vb = s.ref[0] - s.ref[2]; /* V(A u B) - V(A - B) = V(B): they only touch */
        check_op(name, CB_BOOL_UNION, s.a, s.b, s.ref[0], 1e-6, NULL);
        check_op(name, CB_BOOL_INTERSECTION, s.a, s.b, s.ref[1], 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, s.a, s.b, s.ref[2], 1e-6, NULL);
        check_op(name, CB_BOOL_DIFFERENCE, s.b, s.a, vb, 1e-6, NULL);
        cb_model_scenario_clear(&s);
    }
}

/* The tricylinder: unit cylinders along x, y and z, axes meeting at the origin. The Steinmetz
 * solid A n B (itself a Boolean result, its faces trimmed by cut edges) against C: the
 * intersection is the tricylinder, 8 (2 - sqrt 2); union and difference follow from it, the
 * difference being four lobes that touch at four points. */
static void test_tricylinder(int as_nurbs)
{
    double ox[3] = {-2, 0, 0}, x[3] = {1, 0, 0}, oy[3] = {0, -2, 0}, y[3] = {0, 1, 0};
    double oz[3] = {0, 0, -2}, z[3] = {0, 0, 1}, rz[3] = {0, 0, 1}, rx[3] = {1, 0, 0};
    cb_topo_body *A = cylinder(ox, x, rz, 1, 4, as_nurbs), *B = cylinder(oy, y, rz, 1, 4, as_nurbs);
    cb_topo_body *C = cylinder(oz, z, rx, 1, 4, as_nurbs), *AB = NULL;
    cb_error err;
    if (A && B && C) {
        cb_status st = cb_bool_run(&AB, NULL, CB_BOOL_INTERSECTION, A, B, NULL, NULL, &err);
        CHECK(st == CB_OK, "Steinmetz solid: %s", err.msg);
        if (!st) {
            const char *name = as_nurbs ? "tricylinder NURBS" : "tricylinder";
            double tri = 8 * (2 - sqrt(2.0)), ab = 16.0 / 3, c = 4 * PI;
            check_op(name, CB_BOOL_INTERSECTION, AB, C, tri, 1e-6, NULL);
            check_op(name, CB_BOOL_UNION, AB, C, ab + c - tri, 1e-6, NULL);
            /* Four lobes touching at (+-1, 0, 0), (0, +-1, 0). The difference is small
             * (0.647): its error is bounded by 1e-6 of the operand A n B, not of itself (the
             * NURBS one is 8.8e-7 off, 1.4e-6 of its own volume). */
            touching_points = 4;
            check_op(name, CB_BOOL_DIFFERENCE, AB, C, ab - tri, 1e-6 * ab / (ab - tri), NULL);
        }
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
    cb_topo_body_free(C);
    cb_topo_body_free(AB);
}

/* The universal joint of the shared models (../shared/models): the fork against the cross
 * moved by (-100, 0, 0), so that the cross's two cylinders of radius 15 cross the fork's pin
 * hole of the same radius (Steinmetz curves through the cross's own tangent nodes), its
 * z cylinder touches the fork's bore along two lines and grazes the edge of the fork's cradle
 * at a point, and several of its curves cross cylinder seams. Each operation gives a valid
 * result whose mesh passes (A - B touches itself along the two lines: the bore's wall minus
 * the cylinder is two wedges meeting there), and V(A u B) + V(A n B) = V(A) + V(B),
 * V(A - B) = V(A) - V(A n B) within 1e-6. (The curves used to be split off the seams, by the
 * deviation padding of the faces' (u, v) boxes, and a cut ending on a sphere face's edge
 * missed its coarse polygon: 38 edges did not sew.) Moved by (-100, 20, 0) too: the cross's
 * end face lies on the fork's side face, which the fork's cylinder of radius 30 meets along an
 * arc crossing it, and the cross's y cylinder crosses the pin hole with the tangent nodes of
 * the Steinmetz curves at (-30, 100, +-15), where the union and the intersection touch
 * themselves. (The intersection curve along the arc runs along the imprints of two of the
 * side face's edges, not one, and was kept beside them: 14 edges of slivers 0.0035 wide, its
 * chord error, did not sew.) */
static void test_ujoint(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    char path[2][1024];
    cb_topo_body *X[2] = {NULL, NULL};
    cb_error err;
    for (int k = 0; k < 2; k++) {
        snprintf(path[k], sizeof path[k], "%s/models/%s", d ? d : "../shared",
                 k ? "ujoint_cross.step" : "ujoint_fork.step");
        CHECK(cb_step_read(X + k, path[k], &err) == CB_OK, "%s: %s", path[k], err.msg);
    }
    /* per pose: the shift of the cross, and per operation (intersection, union, difference)
     * the points where the result touches itself and whether it does along curves */
    static const struct {
        double shift[3];
        int points[3], curve[3];
    } pose[] = {{{-100, 0, 0}, {0, 0, 0}, {0, 0, 1}}, {{-100, 20, 0}, {2, 2, 0}, {0, 0, 0}}};
    for (int p = 0; p < 2 && X[0] && X[1]; p++) {
        cb_xform t;
        double shift[3];
        for (int k = 0; k < 3; k++)
            shift[k] = pose[p].shift[k] - (p ? pose[p - 1].shift[k] : 0);
        cb_xform_translation(&t, shift);
        cb_topo_body_transform(X[1], &t);
        char name[64];
        snprintf(name, sizeof name, "ujoint %g %g %g", pose[p].shift[0], pose[p].shift[1],
                 pose[p].shift[2]);
        double v[2] = {0, 0}, i = NAN;
        for (int k = 0; k < 2; k++) {
            cb_mass_props mp;
            cb_status st = cb_mass_body(&mp, X[k], 1e-10, NULL, &err);
            CHECK(st == CB_OK, "%s: volume: %s", path[k], err.msg);
            v[k] = st ? NAN : mp.volume;
        }
        const cb_bool_op ops[3] = {CB_BOOL_INTERSECTION, CB_BOOL_UNION, CB_BOOL_DIFFERENCE};
        for (int o = 0; o < 3; o++) {
            touching_points = pose[p].points[o];
            touching_curve = pose[p].curve[o];
            double expected = o == 0 ? -1 : o == 1 ? v[0] + v[1] - i : v[0] - i;
            check_op(name, ops[o], X[0], X[1], expected, o ? 1e-6 : 0, o ? NULL : &i);
        }
    }
    cb_topo_body_free(X[0]);
    cb_topo_body_free(X[1]);
}

/* Shells and solids of a result: a sphere inside a box leaves a void (one solid, two shells),
 * disjoint boxes make two solids, and the Steinmetz difference two solids touching at points. */
static void check_shells(const char *name, cb_bool_op op, const cb_topo_body *A,
                         const cb_topo_body *B, int solids, int shells, double volume)
{
    cb_topo_body *res = NULL;
    cb_error err;
    cb_status st = cb_bool_run(&res, NULL, op, A, B, NULL, NULL, &err);
    CHECK(st == CB_OK, "%s: %s", name, err.msg);
    if (st)
        return;
    CHECK(res->n_solids == solids && res->n_shells == shells, "%s: %d solids, %d shells", name,
          res->n_solids, res->n_shells);
    cb_topo_report r;
    cb_topo_report_init(&r);
    st = cb_topo_validate(&r, res, res->tol, 9, &err);
    CHECK(st == CB_OK && r.n == 0, "%s: not valid: %s", name, st ? err.msg : r.n ? r.items[0] : "");
    cb_topo_report_clear(&r);
    for (int k = 0; k < res->n_solids; k++) {
        const cb_topo_solid *so = res->solids + k;
        double v;
        CHECK(!cb_topo_shell_volume(&v, res, so->first, 64, res->tol, &err) && v > 0,
              "%s: solid %d's first shell not outward", name, k);
        for (int j = so->first + 1; j < so->first + so->count; j++)
            CHECK(!cb_topo_shell_volume(&v, res, j, 64, res->tol, &err) && v < 0,
                  "%s: solid %d's shell %d is not a void", name, k, j);
    }
    cb_mass_props m;
    CHECK(!cb_mass_body(&m, res, 1e-10, NULL, &err) && fabs(m.volume - volume) <= 1e-6 * volume,
          "%s: volume %.12g, expected %.12g", name, m.volume, volume);
    cb_topo_body_free(res);
}

static void test_shells(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {4, 4, 4}, c[3] = {2, 2, 2};
    double lo2[3] = {6, 0, 0}, hi2[3] = {7, 1, 1};
    cb_topo_body *A = box(lo, hi, 0), *S = sphere(c, 1, 0), *D = box(lo2, hi2, 0);
    if (A && S && D) {
        check_shells("sphere inside a box, A - B", CB_BOOL_DIFFERENCE, A, S, 1, 2, 64 - 4 * PI / 3);
        check_shells("sphere inside a box, A u B", CB_BOOL_UNION, A, S, 1, 1, 64);
        check_shells("disjoint boxes, A u B", CB_BOOL_UNION, A, D, 2, 2, 65);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(S);
    cb_topo_body_free(D);
    double ox[3] = {-2, 0, 0}, x[3] = {1, 0, 0}, oy[3] = {0, -2, 0}, y[3] = {0, 1, 0};
    double ref[3] = {0, 0, 1};
    cb_topo_body *X = cylinder(ox, x, ref, 1, 4, 0), *Y = cylinder(oy, y, ref, 1, 4, 0);
    if (X && Y)
        check_shells("Steinmetz, A - B", CB_BOOL_DIFFERENCE, X, Y, 2, 2, 4 * PI - 16.0 / 3);
    cb_topo_body_free(X);
    cb_topo_body_free(Y);
}

/* Cancellation: a progress callback that cancels at its first report (after the intersection
 * stage) stops the operation with CB_ERR_CANCELLED and no result; so does a context cancelled
 * before the call, in the intersection stage. */
static void cancel_at_first(void *user, double fraction, const char *stage)
{
    (void)fraction;
    (void)stage;
    cb_context_cancel(user);
}

static void test_cancel(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2}, c[3] = {1, 1, 2};
    cb_topo_body *A = box(lo, hi, 1), *B = sphere(c, 0.5, 0);
    if (A && B) {
        cb_context ctx;
        cb_context_init(&ctx);
        ctx.progress = cancel_at_first;
        ctx.user = &ctx;
        cb_topo_body *res = NULL;
        cb_error err;
        cb_status st = cb_bool_run(&res, NULL, CB_BOOL_UNION, A, B, NULL, &ctx, &err);
        CHECK(st == CB_ERR_CANCELLED && !res && strstr(err.msg, "cancelled"),
              "cancelled union: status %d, %s", st, err.msg);
        cb_topo_body_free(res);
        /* Cancelled before it starts: the intersection stage stops at its first face pair. */
        cb_context_init(&ctx);
        cb_context_cancel(&ctx);
        res = NULL;
        st = cb_bool_run(&res, NULL, CB_BOOL_UNION, A, B, NULL, &ctx, &err);
        CHECK(st == CB_ERR_CANCELLED && !res && strstr(err.msg, "ssi: cancelled"),
              "union cancelled beforehand: status %d, %s", st, err.msg);
        cb_topo_body_free(res);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* Same body, bit for bit: counts, vertices, edge ranges. */
static int same_body(const cb_topo_body *x, const cb_topo_body *y)
{
    if (x->n_faces != y->n_faces || x->n_edges != y->n_edges || x->n_vertices != y->n_vertices ||
        x->n_coedges != y->n_coedges)
        return 0;
    for (int v = 0; v < x->n_vertices; v++)
        if (memcmp(x->vertices[v].p, y->vertices[v].p, sizeof x->vertices[v].p))
            return 0;
    for (int e = 0; e < x->n_edges; e++)
        if (x->edges[e].t0 != y->edges[e].t0 || x->edges[e].t1 != y->edges[e].t1 ||
            x->edges[e].v[0] != y->edges[e].v[0] || x->edges[e].v[1] != y->edges[e].v[1])
            return 0;
    for (int c = 0; c < x->n_coedges; c++)
        if (x->coedges[c].edge != y->coedges[c].edge || x->coedges[c].sense != y->coedges[c].sense)
            return 0;
    return 1;
}

/* The union of two birds on 1 and on 2 threads, and twice on 2: the same body bit for bit. */
static void test_determinism(const cb_topo_body *A, const cb_topo_body *B)
{
    cb_topo_body *r[3] = {NULL, NULL, NULL};
    int threads[3] = {1, 2, 2};
    for (int k = 0; k < 3; k++) {
        cb_context ctx;
        cb_context_init(&ctx);
        ctx.threads = threads[k];
        cb_error err;
        cb_status st = cb_bool_run(r + k, NULL, CB_BOOL_UNION, A, B, NULL, &ctx, &err);
        CHECK(st == CB_OK, "determinism run %d: %s", k, err.msg);
    }
    if (r[0] && r[1] && r[2]) {
        CHECK(same_body(r[0], r[1]), "union on 1 and 2 threads differs");
        CHECK(same_body(r[1], r[2]), "union differs between two runs on 2 threads");
    }
    for (int k = 0; k < 3; k++)
        cb_topo_body_free(r[k]);
}

static void test_bad_operands(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    cb_topo_body *A = box(lo, hi, 1), *B = box(lo, hi, 1);
    if (!A || !B) {
        cb_topo_body_free(A);
        cb_topo_body_free(B);
        return;
    }
    cb_topo_body *res = (cb_topo_body *)1;
    cb_error err;
    cb_status st = cb_bool_run(&res, NULL, (cb_bool_op)7, A, B, NULL, NULL, &err);
    CHECK(st == CB_ERR_INVALID && !res &&
              check_msg_has(err.msg, (const char *const[]){"operation", NULL}),
          "unknown op: %d %s", st, err.msg);
    int pc = B->coedges[0].pcurve;
    B->coedges[0].pcurve = -1;
    st = cb_bool_run(&res, NULL, CB_BOOL_UNION, A, B, NULL, NULL, &err);
    CHECK(st == CB_ERR_INVALID && !res &&
              check_msg_has(err.msg, (const char *const[]){"operand B", "coedge 0", NULL}),
          "no pcurve: %d %s", st, err.msg);
    B->coedges[0].pcurve = pc;
    /* An open shell: one coedge of an edge moved onto another edge. */
    int e = B->coedges[0].edge;
    B->coedges[0].edge = B->coedges[1].edge;
    cb_topo_body_index(B, &err);
    st = cb_bool_run(&res, NULL, CB_BOOL_UNION, A, B, NULL, NULL, &err);
    CHECK(st == CB_ERR_INVALID &&
              check_msg_has(err.msg, (const char *const[]){"operand B", "not closed", NULL}),
          "open shell: %d %s", st, err.msg);
    B->coedges[0].edge = e;
    cb_topo_body_index(B, &err);
    B->length_unit_mm = 10;
    st = cb_bool_run(&res, NULL, CB_BOOL_UNION, A, B, NULL, NULL, &err);
    CHECK(st == CB_ERR_UNSUPPORTED && !res &&
              check_msg_has(err.msg, (const char *const[]){"length units", NULL}),
          "mixed units: %d %s", st, err.msg);
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* ---------------------------------------------------------------- faces as OCCT writes them */

static cb_topo_body *occt_file(const char *file)
{
    const char *d = getenv("COLIBRI_SOURCE");
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/data/occt/%s", d ? d : ".", file);
    cb_topo_body *b = NULL;
    cb_error err;
    CHECK(cb_step_read(&b, path, &err) == CB_OK, "%s: %s", path, err.msg);
    return b;
}

/* The pair of files[0], files[1] of tests/data/occt into *A, *B (NULL where not read) and their
 * volumes by mass integration into *va, *vb. 1 when both are read and integrate. */
static int occt_pair(cb_topo_body **A, cb_topo_body **B, double *va, double *vb,
                     const char *const files[2])
{
    *A = occt_file(files[0]);
    *B = occt_file(files[1]);
    cb_mass_props ma, mb;
    cb_error err;
    int ok = *A && *B && !cb_mass_body(&ma, *A, 1e-10, NULL, &err) &&
             !cb_mass_body(&mb, *B, 1e-10, NULL, &err);
    CHECK(ok, "%s: operands", files[0]);
    *va = ok ? ma.volume : NAN;
    *vb = ok ? mb.volume : NAN;
    return ok;
}

/* The box lo..hi (analytic faces) in the frame turned by `turn` degrees about z, then moved by
 * m when m is not NULL. */
static cb_topo_body *moved_box(const double lo[3], const double hi[3], double turn,
                               const cb_xform *m)
{
    cb_frame f;
    cb_error err;
    double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, x[3] = {cos(turn * PI / 180), sin(turn * PI / 180), 0};
    cb_topo_body *b = NULL;
    cb_status st = cb_frame_make(&f, o, z, x, &err);
    if (!st)
        st = cb_prim_box(&b, &f, lo, hi, 0, 0, &err);
    CHECK(st == CB_OK, "box: %s", err.msg);
    if (b && m)
        cb_topo_body_transform(b, m);
    return b;
}

/* Faces as Open CASCADE writes them (tests/data/occt/README.md), in Booleans against boxes
 * and a sphere with closed-form volumes, within 1e-6: whole spheres bounded by a VERTEX_LOOP
 * (analytic, B-spline, turned and moved, or with no bound at all) cut by the plane x = 0.3
 * (a cap of height 0.7: pi h^2 (3 r - h) / 3), the lens of two such spheres, cones with their
 * apex on the side face cut below the apex by z = 0.25 (a frustum, and the tip cone with the
 * apex), tori bounded by their two seams or by a VERTEX_LOOP cut by x = 0.3 (the cuts crossing
 * the v seam; the volume by quadrature) and through the axis by x + y = 0 (half the torus; the
 * cuts cross both seams), an ellipsoid (B-spline) cut by z = 0.2. Every result valid, meshed closed without crossings, written as STEP and read back
 * valid with the same volume. (The spheres failed: "face of a sphere surface is not handled",
 * "point in solid: face 0: no loop"; the cones: "face of a cone surface is not handled", and the
 * B-spline cone minus a box meshed with crossing triangles at the apex; the torus cut through
 * its v seam: 18 edges not sewn; the sphere minus the cap read back as the cap.) */
static void test_occt_faces(void)
{
    const double cap_h = 0.7, cap = PI * cap_h * cap_h * (3 - cap_h) / 3, ball = 4 * PI / 3;
    /* The motion of the turned files: the unit quaternion along (0.3, -0.5, 0.7, 0.41)
     * (x, y, z, w), then the shift. */
    double q[4] = {0.3, -0.5, 0.7, 0.41}, qn = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    double o[3] = {0, 0, 0}, axis[3] = {q[0] / qn, q[1] / qn, q[2] / qn};
    cb_xform mv;
    cb_xform_rotation(&mv, o, axis, 2 * acos(q[3] / qn));
    mv.t[0] = 0.123;
    mv.t[1] = -0.377;
    mv.t[2] = 0.219;
    const cb_bool_op ops[3] = {CB_BOOL_INTERSECTION, CB_BOOL_UNION, CB_BOOL_DIFFERENCE};

    static const char *const spheres[] = {"sphere.step", "sphere_nurbs.step",
                                          "sphere_nobound.step", "sphere_rot.step"};
    double lo[3] = {0.3, -2, -2}, hi[3] = {3.3, 2, 2};
    for (int k = 0; k < 4; k++) {
        cb_topo_body *A = occt_file(spheres[k]), *B = moved_box(lo, hi, 0, k == 3 ? &mv : NULL);
        const double want[3] = {cap, 48 + ball - cap, ball - cap};
        for (int o2 = 0; o2 < 3 && A && B; o2++) {
            write_back = 1;
            check_op(spheres[k], ops[o2], A, B, want[o2], 1e-6, NULL);
        }
        cb_topo_body_free(A);
        cb_topo_body_free(B);
    }
    {
        /* The randomized corpus's sphere_edge_2_translated_analytic (bench/corpus): a box and
         * a sphere centred on one of its edges, the sphere's axis and seam in the plane of the
         * box's face y = -0.7226: that face's cut, half a great circle along the seam and the
         * meridian opposite, passes over the pole, where the sphere face (a cap closed by its
         * pole line, no edge) must not call the curve outside (it was cut there, 3 edges
         * unsewn). A quarter inside; the box's sides and the radius as the files give them. */
        double r = 0.356402868109, q = PI / 3 * r * r * r;
        double vbox = 1.78583339544 * 2.024478396279 * 1.615810891731;
        cb_topo_body *A = occt_file("sphere_edge_box.step"),
                     *B = occt_file("sphere_edge_sphere.step");
        const double want[3] = {q, vbox + 3 * q, vbox - q};
        for (int o2 = 0; o2 < 3 && A && B; o2++)
            check_op("sphere on a box edge", ops[o2], A, B, want[o2], 1e-6, NULL);
        cb_topo_body_free(A);
        cb_topo_body_free(B);
    }
    {
        /* r1 = 1 at the origin, r2 = 0.8 at (0.7, 0.1, 0.2) */
        double r1 = 1, r2 = 0.8, d = sqrt(0.54);
        double lens = PI * (r1 + r2 - d) * (r1 + r2 - d) *
                      (d * d + 2 * d * r2 - 3 * r2 * r2 + 2 * d * r1 + 6 * r1 * r2 - 3 * r1 * r1) /
                      (12 * d);
        double v2 = 4 * PI / 3 * r2 * r2 * r2;
        cb_topo_body *A = occt_file("sphere.step"), *B = occt_file("sphere2.step");
        const double want[3] = {lens, ball + v2 - lens, ball - lens};
        for (int o2 = 0; o2 < 3 && A && B; o2++) {
            write_back = 1;
            check_op("spheres lens", ops[o2], A, B, want[o2], 1e-6, NULL);
        }
        cb_topo_body_free(A);
        cb_topo_body_free(B);
    }
    static const char *const cones[] = {"cone.step", "cone_nurbs.step", "cone_rot_nurbs.step"};
    double zlo[3] = {-2, -2, -2}, zhi[3] = {2, 2, 0.25};
    /* base radius 0.8 at z = -0.5, apex at z = 1: cut at z = 0.25, radius 0.4 */
    double frustum = PI * 0.75 / 3 * (0.64 + 0.32 + 0.16), tip = PI * 0.16 * 0.75 / 3;
    for (int k = 0; k < 3; k++) {
        cb_topo_body *A = occt_file(cones[k]), *B = moved_box(zlo, zhi, 0, k == 2 ? &mv : NULL);
        const double want[3] = {frustum, 36 + tip, tip};
        for (int o2 = 0; o2 < 3 && A && B; o2++) {
            write_back = 1;
            check_op(cones[k], ops[o2], A, B, want[o2], 1e-6, NULL);
        }
        cb_topo_body_free(A);
        cb_topo_body_free(B);
    }
    static const char *const tori[] = {"torus.step", "torus_vertex_loop.step",
                                       "torus_nurbs.step"};
    /* R = 1, r = 0.3: the part x >= 0.3 is the integral over the tube's disc of the arc
     * 2 rho acos(0.3 / rho) of each circle about the axis; with rho = R + r sin s it is smooth
     * in s, and Simpson's rule on 4000 intervals gives it to 1e-13. */
    double R = 1, rt = 0.3, part = 0;
    for (int k = 0; k <= 4000; k++) {
        double s = -PI / 2 + PI * k / 4000, rho = R + rt * sin(s);
        double f = 4 * rho * acos(0.3 / rho) * rt * rt * cos(s) * cos(s);
        part += f * (k == 0 || k == 4000 ? 1 : k % 2 ? 4 : 2) * PI / 4000 / 3;
    }
    double hlo[3] = {0, -2, -2}, hhi[3] = {2, 2, 2}, half = PI * PI * R * rt * rt;
    for (int k = 0; k < 3; k++) {
        cb_topo_body *A = occt_file(tori[k]), *B = moved_box(lo, hi, 0, NULL);
        for (int o2 = 0; o2 < 3 && A && B; o2 += 2) {
            write_back = 1;
            check_op(tori[k], ops[o2], A, B, o2 ? 2 * half - part : part, 1e-6, NULL);
        }
        cb_topo_body_free(B);
        /* Through the axis by x + y = 0: half the torus (the B-spline torus' cuts cross
         * both its seams). */
        B = moved_box(hlo, hhi, 45, NULL);
        for (int o2 = 0; o2 < 3 && A && B; o2 += 2) {
            write_back = 1;
            check_op(tori[k], ops[o2], A, B, half, 1e-6, NULL);
        }
        cb_topo_body_free(A);
        cb_topo_body_free(B);
    }
    {
        double a = 1.2, b = 0.8, c = 0.6, h = 0.2, elo[3] = {-2, -2, h}, ehi[3] = {2, 2, 2.2};
        double top = PI * a * b * ((c - h) - (c * c * c - h * h * h) / (3 * c * c));
        double all = 4 * PI / 3 * a * b * c;
        cb_topo_body *A = occt_file("ellipsoid.step"), *B = moved_box(elo, ehi, 0, NULL);
        for (int o2 = 0; o2 < 3 && A && B; o2 += 2) {
            write_back = 1;
            check_op("ellipsoid.step", ops[o2], A, B, o2 ? all - top : top, 1e-6, NULL);
        }
        cb_topo_body_free(A);
        cb_topo_body_free(B);
    }
    {
        /* The randomized corpus's ellipsoid_half_2 (bench/corpus, seed 1), axis-aligned and
         * moved: a B-spline ellipsoid (OCCT's scaled sphere, turned about z) halved by the box
         * face x = 0, which holds its poles. There the traced curve ran out and back along
         * the patch sides that collapse to the poles (folds up to 1.3e-3 long: ssi_tol.h
         * CB_SSI_FOLD); the union of the first pair was left with a loop open in (u, v) at
         * the pole, the moved pair's A - B meshed with an edge of three triangles.
         * V(A n B) = V(A) / 2; V(A) and V(B) by mass integration of the operands. The first
         * pair's A - B meshed with edges of four triangles at a pole: the cut through the
         * pole, split there, kept the far meridian's u at its pole end, and the face's loop
         * ran from the pole across the face (tess_face.c coedge_points); written and read
         * back, the same half meshed as the other half of the ellipsoid, its meridians' lift
         * deciding the side (lift_pole_strip). */
        const char *files[2][2] = {{"ellipsoid_half_axis_a.step", "ellipsoid_half_axis_b.step"},
                                   {"ellipsoid_half_moved_a.step", "ellipsoid_half_moved_b.step"}};
        for (int k = 0; k < 2; k++) {
            cb_topo_body *A, *B;
            double va, vb;
            if (occt_pair(&A, &B, &va, &vb, files[k])) {
                const double want[3] = {va / 2, va / 2 + vb, va / 2};
                for (int o2 = 0; o2 < 3; o2++) {
                    write_back = o2 == 2;
                    check_op(files[k][0], ops[o2], A, B, want[o2], 1e-6, NULL);
                }
            }
            cb_topo_body_free(A);
            cb_topo_body_free(B);
        }
    }
    {
        /* The randomized corpus's sphere_in_cyl_1_axis_analytic (bench/corpus, seed 1): a
         * sphere inside a cylinder of its radius, tangent along a circle; A - B is a void
         * touching the wall. Its mesh crossed itself (23 pairs of triangles): the cut's
         * tangents, with no cross product of parallel normals, were its chords at the ends
         * (the cut's curve left the surfaces by 2e-4 next to its vertices), and the wall's
         * and the void's edges along the circle, two copies of one curve, were sampled apart
         * (tess_edge.c parallel_edges: twins). V(A), V(B) by mass integration. */
        const char *files[2] = {"sphere_in_cyl_a.step", "sphere_in_cyl_b.step"};
        cb_topo_body *A, *B;
        double va, vb;
        if (occt_pair(&A, &B, &va, &vb, files)) {
            void_contact = 1;
            check_op(files[0], CB_BOOL_DIFFERENCE, A, B, va - vb, 1e-6, NULL);
        }
        cb_topo_body_free(A);
        cb_topo_body_free(B);
    }
    {
        /* The randomized corpus's cyl_steinmetz_2 (bench/corpus, seed 1), turned (analytic
         * cylinders) and moved (as B-splines): two cylinders of one radius whose axes cross,
         * both seams through one of the two points where the four intersection curves meet.
         * A curve leaving that node crosses both seams on its first step; the second seam's
         * crossing was not looked for after the first, and the curve kept a jump of a whole
         * period in (u, v) across the face (4 edges unsewn). V(A n B) = 16 R^3 / 3 (R as the
         * files give it), V(A) and V(B) by mass integration of the operands. */
        const double R = 0.638432274775, vi = 16 * R * R * R / 3;
        const char *files[2][2] = {{"steinmetz_seams_rot_a.step", "steinmetz_seams_rot_b.step"},
                                   {"steinmetz_seams_nurbs_a.step",
                                    "steinmetz_seams_nurbs_b.step"}};
        for (int k = 0; k < 2; k++) {
            cb_topo_body *A, *B;
            double va, vb;
            if (occt_pair(&A, &B, &va, &vb, files[k])) {
                const double want[3] = {vi, va + vb - vi, va - vi};
                for (int o2 = 0; o2 < 3; o2++) {
                    touching_points = o2 == 2 ? 2 : 0; /* A - B: two solids meeting at the nodes */
                    check_op(files[k][0], ops[o2], A, B, want[o2], 1e-6, NULL);
                }
            }
            cb_topo_body_free(A);
            cb_topo_body_free(B);
        }
    }
}

/* Area of the disc of radius rho on the side x >= d of a chord at distance d from its centre. */
static double disc_segment(double rho, double d)
{
    return rho <= d ? 0 : rho * rho * acos(d / rho) - d * sqrt(rho * rho - d * d);
}

/* A torus (major radius 1, minor 0.3, axis z through the origin) and the box
 * [0.3, 3.3] x [-2, 2] x [-2, 2], written by Open CASCADE 7.6's STEP writer (tests/data), axis
 * aligned and both turned by one rigid motion (a unit quaternion and a translation of no
 * special values). The box face x = 0.3 is parallel to the torus's axis: its section's folds
 * and its crossings of the tube's top and bottom lie on the rational patches' sides up to the
 * rounding of the coordinates. V(A n B) = integral over z of the section's annulus on x >= 0.3
 * (Gauss-Legendre in the angle z = r sin(theta), 2000 x 8 points: converged to 1e-14). */
static void test_occt_torus(void)
{
    const double R = 1, r = 0.3, d = 0.3, v_torus = 2 * PI * PI * R * r * r, v_box = 48;
    static const double gx[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                 0.9602898564975363},
                        gw[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                 0.1012285362903763};
    double inter = 0;
    const int n = 2000;
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 8; k++) {
            double h = PI / n, th = -PI / 2 + (i + 0.5) * h + (k < 4 ? -1 : 1) * gx[k % 4] * h / 2;
            double w = r * cos(th);
            inter += gw[k % 4] * h / 2 * (disc_segment(R + w, d) - disc_segment(R - w, d)) * w;
        }
    const char *src = getenv("COLIBRI_SOURCE");
    const char *names[2][2] = {{"occt_torus.step", "occt_box.step"},
                               {"occt_torus_turned.step", "occt_box_turned.step"}};
    for (int pose = 0; pose < 2; pose++) {
        cb_topo_body *X[2] = {NULL, NULL};
        for (int k = 0; k < 2; k++) {
            char path[1024];
            cb_error err;
            snprintf(path, sizeof path, "%s/tests/data/%s", src ? src : ".", names[pose][k]);
            CHECK(cb_step_read(X + k, path, &err) == CB_OK, "%s: %s", path, err.msg);
        }
        if (X[0] && X[1]) {
            const char *name = pose ? "OCCT torus, box, turned" : "OCCT torus, box";
            check_op(name, CB_BOOL_UNION, X[0], X[1], v_torus + v_box - inter, 1e-6, NULL);
            check_op(name, CB_BOOL_INTERSECTION, X[0], X[1], inter, 1e-6, NULL);
            check_op(name, CB_BOOL_DIFFERENCE, X[0], X[1], v_torus - inter, 1e-6, NULL);
        }
        cb_topo_body_free(X[0]);
        cb_topo_body_free(X[1]);
    }
    /* Two cylinders of radius 0.6 and length 4 whose axes cross at right angles, as Open
     * CASCADE's NurbsConvert and STEP writer give them in a turned pose (periodic nets of three
     * 120-degree arcs, 13 digits): the Steinmetz solid, 16 r^3 / 3, with its two tangent
     * crossing nodes. */
    cb_topo_body *Y[2] = {NULL, NULL};
    const char *cyl[2] = {"occt_nurbs_cyl_z.step", "occt_nurbs_cyl_x.step"};
    for (int k = 0; k < 2; k++) {
        char path[1024];
        cb_error err;
        snprintf(path, sizeof path, "%s/tests/data/%s", src ? src : ".", cyl[k]);
        CHECK(cb_step_read(Y + k, path, &err) == CB_OK, "%s: %s", path, err.msg);
    }
    if (Y[0] && Y[1]) {
        const double rc = 0.6, v_cyl = PI * rc * rc * 4, v_st = 16 * rc * rc * rc / 3;
        const char *name = "OCCT NURBS Steinmetz";
        check_op(name, CB_BOOL_UNION, Y[0], Y[1], 2 * v_cyl - v_st, 1e-6, NULL);
        check_op(name, CB_BOOL_INTERSECTION, Y[0], Y[1], v_st, 1e-6, NULL);
        touching_points = 2; /* the two halves of A touch at the nodes */
        check_op(name, CB_BOOL_DIFFERENCE, Y[0], Y[1], v_cyl - v_st, 1e-6, NULL);
    }
    cb_topo_body_free(Y[0]);
    cb_topo_body_free(Y[1]);
    /* A torus (R 1.614927371963, r 0.697310653209) and a box whose face is a plane through
     * the torus's axis, in a generic pose, as Open CASCADE writes them (the corpus case
     * torus_half_0_rotated_analytic): the cut runs along the torus's patch sides, where the
     * joined pieces left chords of a fifth of the minor circle. Half the torus, pi^2 R r^2,
     * on each side of the plane; every result valid, written to STEP and read back valid with
     * the same volume (a short edge of a cut shared by several edges was read with its ends
     * the wrong way round). Not checked here: the results' meshes (the cut curve doubles back
     * on itself over 1e-4 near a node, two boundary samples of the torus face coincide and
     * the tessellation stops). */
    cb_topo_body *H[2] = {NULL, NULL};
    const char *half[2] = {"occt_torus_half_a.step", "occt_torus_half_b.step"};
    for (int k = 0; k < 2; k++) {
        char path[1024];
        cb_error err;
        snprintf(path, sizeof path, "%s/tests/data/%s", src ? src : ".", half[k]);
        CHECK(cb_step_read(H + k, path, &err) == CB_OK, "%s: %s", path, err.msg);
    }
    cb_mass_props mb;
    cb_error merr;
    if (H[0] && H[1] && cb_mass_body(&mb, H[1], 1e-12, NULL, &merr) == CB_OK) {
        const double Rt = 1.614927371963, rt = 0.697310653209, vh = PI * PI * Rt * rt * rt;
        const cb_bool_op ops[3] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE};
        const double want[3] = {mb.volume + vh, vh, vh};
        for (int k = 0; k < 3; k++) {
            write_back = no_mesh = 1;
            check_op("OCCT torus half", ops[k], H[0], H[1], want[k], 1e-6, NULL);
        }
    }
    cb_topo_body_free(H[0]);
    cb_topo_body_free(H[1]);
}

/* With an argument, only the named group runs (for debugging): bad, face, corner, steinmetz,
 * brackets, contacts, tricylinder, ujoint, shells, cancel, lens, occt, cardan, birds. */
/* A box on a cube's face standing out of it by 50 tolerances: the union keeps strips of B's
 * four side faces 50 tol wide between the cut along A's face and B's edges, narrower than the
 * weld distance (100 tol), so their short sides weld into points and each strip's long sides
 * end at the same two vertices, within the weld distance of each other. Each long side sews
 * with the piece of its own curve (the cut with A's face, B's edge with B's end face), not with
 * the other side: the strips stay faces and the volume is exact. (B's end face first took the
 * cut's edge, the strips folded onto themselves and came out as shells of their own.) A
 * difference and an intersection keep no strip. */
static void test_sliver(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, lo2[3] = {0.5, 0.2, 0.2};
    double d = 50 * CB_BOOL_REL_TOL * sqrt(3.0); /* the tolerance: 1e-6 of the boxes' diagonal */
    double hi2[3] = {1 + d, 0.8, 0.8};
    cb_topo_body *A = box(lo, hi, 0), *B = box(lo2, hi2, 0);
    if (A && B) {
        double vb = 0.36 * (0.5 + d), vi = 0.36 * 0.5;
        check_op("sliver strips", CB_BOOL_UNION, A, B, 1 + vb - vi, 1e-12, NULL);
        check_op("sliver strips", CB_BOOL_INTERSECTION, A, B, vi, 1e-12, NULL);
        check_op("sliver strips", CB_BOOL_DIFFERENCE, A, B, 1 - vi, 1e-12, NULL);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* Gives every line pcurve of b a parameter that runs ahead of its edge's by up to `ahead` in
 * (u, v) (the same segment as a quadratic B-spline whose middle control point is moved along
 * it by 2 ahead; the ends stay at the edge's ends) and raises the edge tolerances to cover it,
 * as the STEP reader raises them where a file's faces stray from its edges. */
static int pcurves_ahead(cb_topo_body *b, double ahead)
{
    cb_error err;
    for (int c = 0; c < b->n_coedges; c++) {
        if (b->coedges[c].pcurve < 0)
            continue;
        cb_topo_curve *pc = b->pcurves + b->coedges[c].pcurve;
        cb_topo_edge *e = b->edges + b->coedges[c].edge;
        if (pc->kind != CB_CURVE_LINE)
            continue;
        double a[3], z[3], knots[6] = {e->t0, e->t0, e->t0, e->t1, e->t1, e->t1}, pts[9];
        cb_topo_pcurve_eval(a, pc, e->t0);
        cb_topo_pcurve_eval(z, pc, e->t1);
        double len = hypot(z[0] - a[0], z[1] - a[1]);
        for (int i = 0; i < 3; i++) {
            pts[i] = a[i];
            pts[3 + i] = 0.5 * (a[i] + z[i]) + (i < 2 ? 2 * ahead * (z[i] - a[i]) / len : 0);
            pts[6 + i] = z[i];
        }
        cb_topo_curve_clear(pc);
        cb_topo_curve_init(pc);
        pc->kind = CB_CURVE_NURBS;
        if (cb_nurbs_curve_make(pc->nurbs, 2, knots, 6, pts, NULL, 3, &err))
            return -1;
        e->tol = fmax(e->tol, 2 * ahead);
    }
    return 0;
}

/* The largest gap on the surface where one coedge of a loop of b ends and the next begins,
 * each pcurve over the part cb_topo_coedge_pcurve_range gives at its edge's tolerance (as mass
 * properties, tessellation and classification take it). */
static double loop_joint_gap(const cb_topo_body *b)
{
    double worst = 0;
    for (int f = 0; f < b->n_faces; f++) {
        const cb_topo_face *F = b->faces + f;
        cb_topo_inverter inv;
        cb_error err;
        if (cb_topo_inverter_init(&inv, b->surfaces + F->surface, b->tol, &err))
            return HUGE_VAL;
        for (int l = F->first; l < F->first + F->count; l++) {
            const cb_topo_loop *L = b->loops + l;
            for (int k = 0; k < L->count; k++) {
                int c[2] = {L->first + k, L->first + (k + 1) % L->count};
                double uv[2][3], p[2][3], s[2][2];
                for (int i = 0; i < 2; i++) {
                    const cb_topo_edge *e = b->edges + b->coedges[c[i]].edge;
                    cb_topo_coedge_pcurve_range(&s[i][0], &s[i][1], b, c[i], &inv,
                                                fmax(b->tol, e->tol));
                    cb_topo_pcurve_eval(uv[i], b->pcurves + b->coedges[c[i]].pcurve,
                                        s[i][i ? 0 : 1]);
                    cb_topo_inverter_eval(p[i], &inv, uv[i][0], uv[i][1]);
                }
                worst = fmax(worst, hypot(hypot(p[0][0] - p[1][0], p[0][1] - p[1][1]),
                                          p[0][2] - p[1][2]));
            }
        }
        cb_topo_inverter_clear(&inv);
    }
    return worst;
}

/* A's pcurves follow their edges' parameter only within a raised edge tolerance, as a file's
 * may (linkrods.step): 25 tol ahead in the middle (pcurves_ahead), below the weld distance.
 * B crosses A's corner, so its cuts end on A's edges in the middle of their ranges. A piece of
 * such an edge that kept A's pcurve began, at the edge parameter of the cut's end, up to 25
 * tol along the line from where the cut's pcurve ends: the loops of A's faces did not close in
 * (u, v) (loop_joint_gap 24 tol). On a plane, whose edges lie on it, the volume does not show
 * it (mass properties follow the 3D edge); on linkrods' B-spline face 16, whose edge 72 lies
 * 4e-4 off it, the intersection's volume was 1.5e-4 of itself over the same result written and
 * read back (bench_parts draw 0). */
static void test_pcurves_ahead(void)
{
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, lo2[3] = {0.63, -0.41, 0.61};
    double hi2[3] = {1.37, 0.29, 1.23};
    cb_topo_body *A = box(lo, hi, 0), *B = box(lo2, hi2, 0);
    /* the tolerance cb_bool_run takes: 1e-6 of the operands' diagonal */
    double tol = CB_BOOL_REL_TOL * sqrt(1.37 * 1.37 + 1.41 * 1.41 + 1.23 * 1.23);
    CHECK(A && B && pcurves_ahead(A, 25 * tol) == 0, "pcurves ahead: operands");
    if (A && B) {
        double va = 1, vb = 0.74 * 0.70 * 0.62, vi = 0.37 * 0.29 * 0.39;
        check_op("pcurves ahead", CB_BOOL_UNION, A, B, va + vb - vi, 1e-12, NULL);
        check_op("pcurves ahead", CB_BOOL_INTERSECTION, A, B, vi, 1e-12, NULL);
        check_op("pcurves ahead", CB_BOOL_DIFFERENCE, A, B, va - vi, 1e-12, NULL);
        for (int op = 0; op < 3; op++) {
            cb_topo_body *R = NULL;
            cb_error err;
            cb_status st = cb_bool_run(&R, NULL, (cb_bool_op)op, A, B, NULL, NULL, &err);
            double gap = st ? HUGE_VAL : loop_joint_gap(R);
            CHECK(gap <= tol, "pcurves ahead %s: loops open by %.3g in (u, v) (tol %.3g)",
                  cb_bool_op_name((cb_bool_op)op), gap, tol);
            cb_topo_body_free(R);
        }
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    const char *only = argc > 1 ? argv[1] : NULL;
    if (!only || !strcmp(only, "bad"))
        test_bad_operands();
    if (!only || !strcmp(only, "face")) {
        test_sphere_on_face(0);
        test_sphere_on_face(1);
    }
    if (!only || !strcmp(only, "corner")) {
        test_sphere_on_corner(0);
        test_sphere_on_corner(1);
    }
    if (!only || !strcmp(only, "steinmetz")) {
        double z[3] = {0, 0, 1}, d[3] = {0, 0.6, 0.8};
        test_steinmetz(0, z, "steinmetz");
        test_steinmetz(0, d, "steinmetz seams off");
        test_steinmetz(1, z, "steinmetz NURBS");
        test_steinmetz(1, d, "steinmetz NURBS seams off");
    }
    if (!only || !strcmp(only, "lens")) {
        test_lens_torus(0);
        test_lens_torus(1);
    }
    if (!only || !strcmp(only, "revolved"))
        test_revolved();
    if (!only || !strcmp(only, "occt"))
        test_occt_faces();
    if (!only || !strcmp(only, "brackets"))
        test_brackets();
    if (!only || !strcmp(only, "contacts")) {
        test_contacts(0);
        test_contacts(1);
        test_voids(0);
        test_voids(1);
    }
    if (!only || !strcmp(only, "tricylinder")) {
        test_tricylinder(0);
        test_tricylinder(1);
    }
    if (!only || !strcmp(only, "ujoint"))
        test_ujoint();
    if (!only || !strcmp(only, "occt"))
        test_occt_torus();
    if (!only || !strcmp(only, "shells")) {
        test_shells();
        test_sliver();
        test_pcurves_ahead();
    }
    if (!only || !strcmp(only, "cancel"))
        test_cancel();
    if (!only || !strcmp(only, "cardan")) {
        test_cardan(0);
        test_cardan(1);
        test_crosses_side(0);
        test_crosses_side(1);
        test_crosses_shifted(0);
        test_crosses_shifted(1);
    }
    if (!only || !strcmp(only, "birds")) {
        test_birds();
        test_birds_fig12();
    }
    return check_report("test_bool_op");
}
