/* Primitive solids (brep/prim.c): every builder, analytic and B-spline faces, several poses:
 * valid bodies (cb_topo_validate, no problem), the documented counts, vertices and edges on
 * the shape's closed-form surface, and bad sizes rejected with a message. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "brep/prim.h"
#include "check.h"

static const double PI = 3.14159265358979323846;

enum { BOX, SPHERE, ELLIPSOID, CYLINDER, FRUSTUM, CONE_UP, CONE_DOWN, TORUS, N_SHAPES };

static const char *const shape_name[N_SHAPES] = {
    "box",     "sphere",         "ellipsoid",        "cylinder",
    "frustum", "cone (apex up)", "cone (apex down)", "torus"};

/* Documented counts: faces, edges, vertices. */
static const int counts[N_SHAPES][3] = {{6, 12, 8}, {1, 1, 2}, {1, 1, 2}, {3, 3, 2},
                                        {3, 3, 2},  {2, 2, 2}, {2, 2, 2}, {2, 4, 2}};

static cb_status build(cb_topo_body **b, int shape, const cb_frame *f, int as_nurbs, cb_error *err)
{
    const double lo[3] = {-1, -0.5, 0.25}, hi[3] = {2, 1.5, 1.25};
    switch (shape) {
    case BOX: return cb_prim_box(b, f, lo, hi, as_nurbs, 0, err);
    case SPHERE: return cb_prim_sphere(b, f, 1.5, as_nurbs, 0, err);
    case ELLIPSOID: return cb_prim_ellipsoid(b, f, 2, 1, 0.5, as_nurbs, 0, err);
    case CYLINDER: return cb_prim_cylinder(b, f, 0.75, 2, as_nurbs, 0, err);
    case FRUSTUM: return cb_prim_cone(b, f, 1, 0.5, 1.5, as_nurbs, 0, err);
    case CONE_UP: return cb_prim_cone(b, f, 1.25, 0, 2, as_nurbs, 0, err);
    case CONE_DOWN: return cb_prim_cone(b, f, 0, 1.25, 2, as_nurbs, 0, err);
    default: return cb_prim_torus(b, f, 2, 0.5, as_nurbs, 0, err);
    }
}

/* Implicit value of the shape's boundary in local coordinates, zero on the surface of some
 * face: a point of an edge or a vertex must make it (nearly) vanish. */
static double on_shape(int shape, const double l[3])
{
    double x = l[0], y = l[1], z = l[2], rho = hypot(x, y);
    switch (shape) {
    case BOX: {
        const double lo[3] = {-1, -0.5, 0.25}, hi[3] = {2, 1.5, 1.25};
        double d = HUGE_VAL, out = 0;
        for (int i = 0; i < 3; i++) {
            d = fmin(d, fmin(fabs(l[i] - lo[i]), fabs(l[i] - hi[i])));
            out = fmax(out, fmax(lo[i] - l[i], l[i] - hi[i]));
        }
        return fmax(d, out);
    }
    case SPHERE: return fabs(hypot(rho, z) - 1.5);
    case ELLIPSOID: return fabs(x * x / 4 + y * y + 4 * z * z - 1);
    case CYLINDER: return fmin(fabs(rho - 0.75), fmin(fabs(z), fabs(z - 2)));
    case FRUSTUM: return fmin(fabs(rho - (1 - z / 3)), fmin(fabs(z), fabs(z - 1.5)));
    case CONE_UP: return fmin(fabs(rho - 1.25 * (1 - z / 2)), fabs(z));
    case CONE_DOWN: return fmin(fabs(rho - 1.25 * z / 2), fabs(z - 2));
    default: return fabs(hypot(rho - 2, z) - 0.5);
    }
}

static void random_frame(cb_frame *f, check_rng *rng, int pose)
{
    double o[3], z[3], x[3];
    for (int i = 0; i < 3; i++) {
        o[i] = pose ? check_rng_uniform(rng, -50, 50) : 0;
        z[i] = pose ? check_rng_uniform(rng, -1, 1) : i == 2;
        x[i] = pose ? check_rng_uniform(rng, -1, 1) : i == 0;
    }
    cb_error err;
    CHECK(cb_frame_make(f, o, z, x, &err) == CB_OK, "frame: %s", err.msg);
}

static void check_shape(int shape, int as_nurbs, const cb_frame *f, int pose)
{
    const char *name = shape_name[shape];
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = build(&b, shape, f, as_nurbs, &err);
    CHECK(st == CB_OK && b, "%s nurbs %d pose %d: %s", name, as_nurbs, pose, err.msg);
    if (st)
        return;
    CHECK(b->n_faces == counts[shape][0] && b->n_edges == counts[shape][1] &&
              b->n_vertices == counts[shape][2] && b->n_shells == 1 && b->n_solids == 1,
          "%s: %d faces, %d edges, %d vertices, %d shells, %d solids", name, b->n_faces, b->n_edges,
          b->n_vertices, b->n_shells, b->n_solids);
    int kinds_ok = 1;
    for (int k = 0; k < b->n_surfaces; k++)
        kinds_ok &= b->surfaces[k].kind == (as_nurbs ? CB_SURFACE_NURBS : CB_SURFACE_ANALYTIC);
    CHECK(kinds_ok, "%s nurbs %d: a face of another kind", name, as_nurbs);
    int all_pcurves = 1;
    for (int c = 0; c < b->n_coedges; c++)
        all_pcurves &= b->coedges[c].pcurve >= 0;
    CHECK(all_pcurves, "%s nurbs %d: a coedge without pcurve", name, as_nurbs);
    /* Vertices and 9 points per edge on the closed-form shape. */
    double dev = 0;
    for (int v = 0; v < b->n_vertices; v++) {
        double l[3];
        cb_frame_to_local(l, f, b->vertices[v].p);
        dev = fmax(dev, on_shape(shape, l));
    }
    for (int e = 0; e < b->n_edges; e++)
        for (int k = 0; k <= 8; k++) {
            const cb_topo_edge *ed = &b->edges[e];
            double p[3];
            cb_topo_curve_eval(p, &b->curves[ed->curve], ed->t0 + (ed->t1 - ed->t0) * k / 8);
            cb_frame_to_local(p, f, p);
            dev = fmax(dev, on_shape(shape, p));
        }
    CHECK(dev < 1e-12 * 64, "%s pose %d: edge point %g off the shape", name, pose, dev);
    cb_topo_report r;
    cb_topo_report_init(&r);
    st = cb_topo_validate(&r, b, 0, 9, &err);
    CHECK(st == CB_OK && r.n == 0, "%s nurbs %d pose %d: %d problems, first: %s", name, as_nurbs,
          pose, r.n, r.n ? r.items[0] : err.msg);
    /* The surfaces are exact: the edges lie on them to round-off, far below the tolerance. */
    CHECK(r.max_edge_surface < 1e-12 * 64, "%s nurbs %d: edge-surface deviation %g", name, as_nurbs,
          r.max_edge_surface);
    cb_topo_report_clear(&r);
    /* The same body turned inside out (each face's sense and the direction of its loops
     * reversed, so that the loops still run round the same region) must fail the
     * orientation check. */
    for (int k = 0; k < b->n_shells; k++)
        cb_topo_shell_reverse(b, k);
    st = cb_topo_body_index(b, &err);
    CHECK(st == CB_OK, "%s: index after reversal: %s", name, err.msg);
    cb_topo_report_init(&r);
    cb_topo_validate(&r, b, 0, 9, &err);
    CHECK(r.n >= 1 && strstr(r.items[0], "inward"), "%s flipped: %d problems", name, r.n);
    cb_topo_report_clear(&r);
    cb_topo_body_free(b);
}

/* A B-spline circle with rounded weights must still be a circle to round-off: the exact form
 * (weights cos(pi/4) rounded) costs nothing measurable. */
static void check_nurbs_exactness(void)
{
    cb_topo_body *b;
    cb_error err;
    if (cb_prim_sphere(&b, NULL, 1, 1, 0, &err)) {
        CHECK(0, "sphere: %s", err.msg);
        return;
    }
    double dev = 0;
    for (int i = 0; i <= 64; i++)
        for (int j = 0; j <= 64; j++) {
            double d[6][3];
            cb_nurbs_surface_eval_derivs(d, b->surfaces[0].nurbs, 2 * PI * i / 64,
                                         -PI / 2 + PI * j / 64);
            dev = fmax(dev, fabs(cb_vec3_norm(d[0]) - 1));
        }
    CHECK(dev < 1e-15, "B-spline unit sphere: radius off by %g", dev);
    printf("B-spline unit sphere: largest radius error %.3g\n", dev);
    cb_topo_body_free(b);
}

/* b must have been reset to NULL by the builder (it starts non-NULL). */
static cb_topo_body *b_bad;

static void expect_invalid(cb_status st, const cb_error *err, const char *part)
{
    CHECK(st == CB_ERR_INVALID && !b_bad && strstr(err->msg, part),
          "expected rejection mentioning '%s', got status %d: %s", part, st, err->msg);
    b_bad = (cb_topo_body *)&b_bad;
}

static void check_bad_sizes(void)
{
    b_bad = (cb_topo_body *)&b_bad;
    cb_error err;
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, flat[3] = {1, 0, 1};
    expect_invalid(cb_prim_box(&b_bad, NULL, lo, flat, 0, 0, &err), &err, "y range");
    hi[2] = NAN;
    expect_invalid(cb_prim_box(&b_bad, NULL, lo, hi, 0, 0, &err), &err, "z range");
    expect_invalid(cb_prim_sphere(&b_bad, NULL, 0, 0, 0, &err), &err, "radius");
    expect_invalid(cb_prim_sphere(&b_bad, NULL, -1, 1, 0, &err), &err, "radius");
    expect_invalid(cb_prim_sphere(&b_bad, NULL, NAN, 0, 0, &err), &err, "radius");
    expect_invalid(cb_prim_ellipsoid(&b_bad, NULL, 1, 0, 1, 0, 0, &err), &err, "semi-axis b");
    expect_invalid(cb_prim_ellipsoid(&b_bad, NULL, 1, 1, INFINITY, 0, 0, &err), &err,
                   "semi-axis c");
    expect_invalid(cb_prim_cylinder(&b_bad, NULL, 1, 0, 0, 0, &err), &err, "height");
    expect_invalid(cb_prim_cylinder(&b_bad, NULL, -1, 1, 0, 0, &err), &err, "radius");
    expect_invalid(cb_prim_cone(&b_bad, NULL, 1, 1, 1, 0, 0, &err), &err, "equal radii");
    expect_invalid(cb_prim_cone(&b_bad, NULL, 0, 0, 1, 0, 0, &err), &err, "equal radii");
    expect_invalid(cb_prim_cone(&b_bad, NULL, 1, -0.5, 1, 0, 0, &err), &err, ">= 0");
    expect_invalid(cb_prim_cone(&b_bad, NULL, 1, 0.5, -1, 0, 0, &err), &err, "height");
    expect_invalid(cb_prim_torus(&b_bad, NULL, 1, 1, 0, 0, &err), &err, "below the major");
    expect_invalid(cb_prim_torus(&b_bad, NULL, 1, 2, 1, 0, &err), &err, "below the major");
    expect_invalid(cb_prim_torus(&b_bad, NULL, 1, 0, 0, 0, &err), &err, "minor radius");
    expect_invalid(cb_prim_sphere(&b_bad, NULL, 1, 0, NAN, &err), &err, "tolerance");
    cb_frame f = {{0, NAN, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    expect_invalid(cb_prim_sphere(&b_bad, &f, 1, 0, 0, &err), &err, "frame");
}

int main(void)
{
    check_rng rng = {2024};
    for (int shape = 0; shape < N_SHAPES; shape++)
        for (int as_nurbs = 0; as_nurbs < 2; as_nurbs++)
            for (int pose = 0; pose < 3; pose++) {
                cb_frame f;
                random_frame(&f, &rng, pose);
                check_shape(shape, as_nurbs, &f, pose);
            }
    check_nurbs_exactness();
    check_bad_sizes();
    return check_report("test_brep_prim");
}
