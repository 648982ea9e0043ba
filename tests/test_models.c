/* Model generators (models/): the hummingbird is a valid, watertight, outward-oriented closed
 * solid of 312 bicubic 6 x 6 B-spline faces; its pose is rigid; it survives a STEP round trip
 * exactly; two posed birds overlap as in the paper's Fig. 12; the `colibri model` command. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "check_cli.h"
#include "brep/mass.h"
#include "brep/prim.h"
#include "io/step.h"
#include "io/step_write.h"
#include "models/models.h"

static const double PI = 3.14159265358979323846;

/* Tolerances of the checks, relative to the model size (its largest vertex coordinate). */
static const double VALIDATE_REL_TOL = 1e-9; /* edges on faces, loop gaps, vertices */
static const double POSE_REL_TOL = 1e-12;    /* rigid motion of vertices and volume */
static const double MESH_REL_TOL = 2e-3;     /* divergence volume against the mesh volume */

static double seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double body_size(const cb_topo_body *b)
{
    double size = 0;
    for (int k = 0; k < b->n_vertices; k++)
        for (int c = 0; c < 3; c++)
            size = fmax(size, fabs(b->vertices[k].p[c]));
    return size;
}

static const double *ctrl(const cb_topo_body *b, int f, int i, int j)
{
    return cb_nurbs_surface_cw(b->surfaces[b->faces[f].surface].nurbs, i, j);
}

/* ---------------------------------------------------------------- volume ------------------- */

/* Volume by the divergence theorem, V = 1/3 sum over faces of the integral of S . (S_u x S_v)
 * (negated where same_sense = 0), with 5-point Gauss-Legendre per knot span: the integrand is
 * a polynomial of degree 8 in each parameter on a span, so the rule is exact to round-off. */
static double volume_exact(const cb_topo_body *b)
{
    static const double gx[5] = {-0.906179845938664, -0.538469310105683, 0.0, 0.538469310105683,
                                 0.906179845938664};
    static const double gw[5] = {0.236926885056189, 0.478628670499366, 0.568888888888889,
                                 0.478628670499366, 0.236926885056189};
    double vol = 0;
    for (int f = 0; f < b->n_faces; f++) {
        const cb_nurbs_surface_struct *s = b->surfaces[b->faces[f].surface].nurbs;
        double sum = 0;
        for (int su = s->deg_u; su < s->n_u; su++)
            for (int sv = s->deg_v; sv < s->n_v; sv++) {
                double u0 = s->knots_u[su], u1 = s->knots_u[su + 1];
                double v0 = s->knots_v[sv], v1 = s->knots_v[sv + 1];
                for (int a = 0; a < 5; a++)
                    for (int c = 0; c < 5; c++) {
                        double d[6][3], n[3];
                        cb_nurbs_surface_eval_derivs(d, s, u0 + (u1 - u0) * (gx[a] + 1) / 2,
                                                     v0 + (v1 - v0) * (gx[c] + 1) / 2);
                        cb_vec3_cross(n, d[1], d[2]);
                        sum += gw[a] * gw[c] * (u1 - u0) * (v1 - v0) / 4 * cb_vec3_dot(d[0], n);
                    }
            }
        vol += (b->faces[f].same_sense ? sum : -sum) / 3;
    }
    return vol;
}

/* Evaluates face f at parameters (i, j) / (n - 1) of its domain. */
static void face_point(double p[3], const cb_topo_body *b, int f, int i, int j, int n)
{
    const cb_nurbs_surface_struct *s = b->surfaces[b->faces[f].surface].nurbs;
    double box[4];
    cb_nurbs_surface_domain(s, box);
    cb_nurbs_surface_eval(p, s, box[0] + (box[1] - box[0]) * i / (n - 1),
                          box[2] + (box[3] - box[2]) * j / (n - 1));
}

/* Volume of the triangle mesh of an n x n grid per face (signed tetrahedra to the origin): an
 * estimate independent of the quadrature that converges as O(1 / n^2). */
static double volume_mesh(const cb_topo_body *b, int n)
{
    double vol = 0, *g = malloc(sizeof *g * 3 * (size_t)n * n);
    for (int f = 0; f < b->n_faces; f++) {
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                face_point(g + 3 * (i * n + j), b, f, i, j, n);
        double sum = 0;
        for (int i = 0; i + 1 < n; i++)
            for (int j = 0; j + 1 < n; j++) {
                const double *p00 = g + 3 * (i * n + j), *p10 = g + 3 * ((i + 1) * n + j);
                const double *p01 = g + 3 * (i * n + j + 1), *p11 = g + 3 * ((i + 1) * n + j + 1);
                double c[3];
                cb_vec3_cross(c, p10, p11);
                sum += cb_vec3_dot(p00, c);
                cb_vec3_cross(c, p11, p01);
                sum += cb_vec3_dot(p00, c);
            }
        vol += (b->faces[f].same_sense ? sum : -sum) / 6;
    }
    free(g);
    return vol;
}

/* ---------------------------------------------------------------- structure ---------------- */

static void check_structure(const cb_topo_body *b)
{
    CHECK(b->n_solids == 1 && b->n_shells == 1 && b->shells[0].closed && b->n_faces == 312 &&
              b->n_loops == 312 && b->n_coedges == 4 * 312 && b->n_edges == 624 &&
              b->n_vertices == 314,
          "counts: %d solids, %d shells, %d faces, %d loops, %d coedges, %d edges, %d vertices",
          b->n_solids, b->n_shells, b->n_faces, b->n_loops, b->n_coedges, b->n_edges,
          b->n_vertices);
    static const double knots[10] = {0, 0, 0, 0, 1 / 3.0, 2 / 3.0, 1, 1, 1, 1};
    int bad = 0;
    for (int f = 0; f < b->n_faces; f++) {
        const cb_topo_surface *s = &b->surfaces[b->faces[f].surface];
        int ok = s->kind == CB_SURFACE_NURBS && s->nurbs->deg_u == 3 && s->nurbs->deg_v == 3 &&
                 s->nurbs->n_u == 6 && s->nurbs->n_v == 6 &&
                 !memcmp(s->nurbs->knots_u, knots, sizeof knots) &&
                 !memcmp(s->nurbs->knots_v, knots, sizeof knots);
        for (int k = 0; ok && k < 36; k++)
            ok = s->nurbs->cw[4 * k + 3] == 1.0;
        if (!ok && bad++ < 5)
            CHECK(0, "face %d: not a polynomial bicubic 6 x 6 clamped uniform B-spline", f);
    }
    CHECK(bad == 0, "%d faces are not bicubic 6 x 6", bad);
}

/* The boundary rows of face f in loop order (0,0) -> (1,0) -> (1,1) -> (0,1) -> (0,0), 6
 * points each, traversal direction. */
static void face_rows(const double *rows[4][6], const cb_topo_body *b, int f)
{
    for (int k = 0; k < 6; k++) {
        rows[0][k] = ctrl(b, f, k, 0);
        rows[1][k] = ctrl(b, f, 5, k);
        rows[2][k] = ctrl(b, f, 5 - k, 5);
        rows[3][k] = ctrl(b, f, 0, 5 - k);
    }
}

/* Parameters (u, v) of face f on side `side` of face_rows at traversal fraction t. */
static void side_param(double *u, double *v, int side, double t)
{
    const double uu[4] = {t, 1, 1 - t, 0}, vv[4] = {0, t, 1, 1 - t};
    *u = uu[side];
    *v = vv[side];
}

/* Watertightness and continuity: every coedge's edge curve, in traversal order, is
 * bit-identical to one boundary row of its face in loop order, and the vertices are the row
 * ends. Reports the largest normal angle between the two faces along each edge. */
static void check_watertight(const cb_topo_body *b)
{
    int mismatched = 0, side_of[4 * 312];
    for (int c = 0; c < b->n_coedges; c++) {
        const cb_topo_coedge *ce = &b->coedges[c];
        const cb_topo_edge *e = &b->edges[ce->edge];
        const cb_nurbs_curve_struct *cv = b->curves[e->curve].nurbs;
        int f = b->loops[ce->loop].face, forward = ce->sense == e->same_sense, found = -1;
        const double *rows[4][6];
        face_rows(rows, b, f);
        for (int side = 0; side < 4 && found < 0 && cv->n == 6; side++) {
            int same = 1;
            for (int k = 0; k < 6 && same; k++) {
                const double *q = cv->cw + 4 * (forward ? k : 5 - k);
                same = !memcmp(q, rows[side][k], 3 * sizeof(double)) && q[3] == 1.0;
            }
            if (same)
                found = side;
        }
        side_of[c] = found;
        const double *start = b->vertices[e->v[ce->sense ? 0 : 1]].p;
        if (found < 0 || memcmp(start, rows[found][0], sizeof(double) * 3)) {
            if (mismatched++ < 5)
                CHECK(0, "coedge %d (face %d, edge %d): no boundary row of the face is "
                         "bit-identical to the edge curve, or the start vertex differs",
                      c, f, ce->edge);
        }
    }
    CHECK(mismatched == 0, "%d coedges do not share their face's boundary row exactly",
          mismatched);
    if (mismatched)
        return;
    /* Normals across edges: C2 inside a box side (angle ~ 0), G1 up to the fit elsewhere. */
    double worst = 0;
    int kinked = 0;
    for (int e = 0; e < b->n_edges; e++) {
        int c0 = b->edge_coedges[b->edge_start[e]], c1 = b->edge_coedges[b->edge_start[e] + 1];
        double angle = 0;
        for (int k = 0; k <= 8; k++) {
            double n[2][3];
            for (int h = 0; h < 2; h++) {
                int c = h ? c1 : c0, f = b->loops[b->coedges[c].loop].face;
                /* Both coedges at the same point: the second runs the other way. */
                double u, v, d[6][3];
                side_param(&u, &v, side_of[c], h ? 1 - k / 8.0 : k / 8.0);
                cb_nurbs_surface_eval_derivs(d, b->surfaces[b->faces[f].surface].nurbs, u, v);
                cb_vec3_cross(n[h], d[1], d[2]);
                cb_vec3_normalize(n[h]);
            }
            angle = fmax(angle, acos(fmin(1, cb_vec3_dot(n[0], n[1]))));
        }
        worst = fmax(worst, angle);
        kinked += angle > 1e-6;
    }
    printf("normal angle across edges: %d of %d edges above 1e-6 rad, largest %.2f degrees\n",
           kinked, b->n_edges, worst * 180 / PI);
    /* The 88 edges on the box's 12 edges (4 x 10 + 8 x 6) may kink; the others are C2. */
    CHECK(kinked <= 88, "%d edges with a normal jump, at most the 88 box edges expected", kinked);
    CHECK(worst < 10 * PI / 180, "normal jump %.2f degrees across an edge", worst * 180 / PI);
}

static void check_valid(cb_topo_body *b, const char *what)
{
    cb_topo_report r;
    cb_topo_report_init(&r);
    cb_error err;
    double tol = VALIDATE_REL_TOL * body_size(b);
    CHECK(cb_topo_validate(&r, b, tol, 9, &err) == CB_OK, "%s: validate: %s", what, err.msg);
    CHECK(r.n == 0, "%s: %d problems at tolerance %g, first: %s", what, r.n, tol,
          r.n ? r.items[0] : "");
    printf("%s: valid at tolerance %.2g; edge-surface %.2g, loop gap %.2g, edge-vertex %.2g\n",
           what, tol, r.max_edge_surface, r.max_loop_gap, r.max_edge_vertex);
    cb_topo_report_clear(&r);
}

/* ---------------------------------------------------------------- scenarios ---------------- */

static cb_topo_body *make_bird(const cb_hummingbird_params *p)
{
    cb_topo_body *b = NULL;
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_model_hummingbird(&b, p, &err);
    CHECK(st == CB_OK && b, "hummingbird: %s", err.msg);
    return b;
}

/* The second bird of the overlap scenario: turned 40 degrees about a tilted vertical axis and
 * shifted by a fraction of its length, so bodies, wings and tails cross as in Fig. 12. */
static void fig12_pose(cb_hummingbird_params *p)
{
    cb_hummingbird_params_default(p);
    p->wing_angle_deg = 5;
    p->axis[0] = 0.2;
    p->axis[1] = 0.3;
    p->axis[2] = 1;
    p->angle_deg = 40;
    p->translate[0] = 0.4;
    p->translate[1] = 0.25;
    p->translate[2] = 0.15;
}

static void test_default(void)
{
    cb_hummingbird_params p;
    cb_hummingbird_params_default(&p);
    double t0 = seconds();
    cb_topo_body *b = make_bird(&p);
    printf("hummingbird built in %.3f s\n", seconds() - t0);
    if (!b)
        return;
    check_structure(b);
    check_valid(b, "hummingbird");
    check_watertight(b);
    double margin = 0;
    cb_error err;
    CHECK(cb_model_hummingbird_margin(&margin, b, &p, 31, &err) == CB_OK && margin > 0,
          "no-fold margin %g: %s", margin, err.msg);
    double v = volume_exact(b), vm = volume_mesh(b, 33);
    printf("volume %.12g (mesh of 32 x 32 cells a face: %.12g, relative difference %.2g), "
           "no-fold margin %.3g\n",
           v, vm, fabs(v - vm) / v, margin);
    CHECK(v > 0, "volume %g: faces point inward", v);
    CHECK(fabs(v - vm) <= MESH_REL_TOL * v, "volume %.12g, mesh volume %.12g", v, vm);
    cb_topo_body_free(b);
}

static void test_pose(void)
{
    cb_hummingbird_params p, q;
    cb_hummingbird_params_default(&p);
    q = p;
    q.scale = 1.5;
    q.axis[0] = 1;
    q.axis[1] = 2;
    q.axis[2] = 3;
    q.angle_deg = 37;
    q.translate[0] = 0.3;
    q.translate[1] = -2;
    q.translate[2] = 5;
    cb_topo_body *a = make_bird(&p), *b = make_bird(&q);
    if (a && b) {
        cb_xform x;
        const double o[3] = {0, 0, 0};
        cb_xform_rotation(&x, o, q.axis, q.angle_deg * PI / 180);
        memcpy(x.t, q.translate, sizeof x.t);
        double worst = 0;
        for (int k = 0; k < a->n_vertices && k < b->n_vertices; k++) {
            double s[3], t[3];
            for (int c = 0; c < 3; c++)
                s[c] = q.scale * a->vertices[k].p[c];
            cb_xform_apply_point(t, &x, s);
            worst = fmax(worst, cb_vec3_dist(t, b->vertices[k].p));
        }
        double va = volume_exact(a), vb = volume_exact(b), s3 = q.scale * q.scale * q.scale;
        CHECK(worst <= POSE_REL_TOL * body_size(b), "posed vertices off by %g", worst);
        CHECK(fabs(vb - s3 * va) <= POSE_REL_TOL * vb, "volume %.17g posed, %.17g expected", vb,
              s3 * va);
        check_valid(b, "posed hummingbird");
        printf("pose: vertices within %.2g of R (s p) + t, volume %.12g = %.12g s^3\n", worst, vb,
               va);
    }
    cb_topo_body_free(a);
    cb_topo_body_free(b);
}

static void test_step_round_trip(void)
{
    cb_hummingbird_params p;
    fig12_pose(&p);
    cb_topo_body *a = make_bird(&p), *b = NULL;
    if (!a)
        return;
    char path[256];
    snprintf(path, sizeof path, "/tmp/colibri_bird_%d.step", (int)getpid());
    cb_error err;
    cb_error_clear(&err);
    CHECK(cb_step_write(a, path, "hummingbird", &err) == CB_OK, "write: %s", err.msg);
    CHECK(cb_step_read(&b, path, &err) == CB_OK, "read back: %s", err.msg);
    if (b) {
        CHECK(b->n_faces == a->n_faces && b->n_edges == a->n_edges &&
                  b->n_vertices == a->n_vertices && b->n_coedges == a->n_coedges &&
                  b->n_solids == 1,
              "counts changed: faces %d, edges %d, vertices %d", b->n_faces, b->n_edges,
              b->n_vertices);
        int moved = 0;
        for (int f = 0; f < a->n_faces && f < b->n_faces; f++) {
            const cb_nurbs_surface_struct *sa = a->surfaces[a->faces[f].surface].nurbs;
            const cb_nurbs_surface_struct *sb = b->surfaces[b->faces[f].surface].nurbs;
            int same = b->surfaces[b->faces[f].surface].kind == CB_SURFACE_NURBS &&
                       sb->n_u == 6 && sb->n_v == 6 &&
                       !memcmp(sa->knots_u, sb->knots_u, sizeof(double) * 10) &&
                       !memcmp(sa->knots_v, sb->knots_v, sizeof(double) * 10) &&
                       !memcmp(sa->cw, sb->cw, sizeof(double) * 4 * 36) &&
                       a->faces[f].same_sense == b->faces[f].same_sense;
            moved += !same;
        }
        CHECK(moved == 0, "%d faces changed in the round trip", moved);
        check_valid(b, "hummingbird read back from STEP");
        printf("STEP round trip: %d faces, %d faces changed\n", b->n_faces, moved);
    }
    remove(path);
    cb_topo_body_free(a);
    cb_topo_body_free(b);
}

/* ---------------------------------------------------------------- overlap ------------------ */

static void net_box(cb_aabb *box, const cb_topo_body *b, int f)
{
    const cb_nurbs_surface_struct *s = b->surfaces[b->faces[f].surface].nurbs;
    cb_aabb_of_points(box, s->cw, 36, 4);
}

/* Sign of the volume of the tetrahedron (a, b, c, d). */
static double orient(const double a[3], const double b[3], const double c[3], const double d[3])
{
    double u[3], v[3], w[3], x[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    cb_vec3_cross(x, u, v);
    return cb_vec3_dot(x, w);
}

/* Segment pq crosses triangle abc (general position: strict signs). */
static int segment_hits(const double p[3], const double q[3], const double *t[3])
{
    double sp = orient(t[0], t[1], t[2], p), sq = orient(t[0], t[1], t[2], q);
    if ((sp > 0) == (sq > 0) || sp == 0 || sq == 0)
        return 0;
    double a = orient(p, q, t[0], t[1]), b = orient(p, q, t[1], t[2]), c = orient(p, q, t[2], t[0]);
    return (a > 0 && b > 0 && c > 0) || (a < 0 && b < 0 && c < 0);
}

static int triangles_meet(const double *s[3], const double *t[3])
{
    for (int k = 0; k < 3; k++)
        if (segment_hits(s[k], s[(k + 1) % 3], t) || segment_hits(t[k], t[(k + 1) % 3], s))
            return 1;
    return 0;
}

/* Whether the n x n grid meshes of face fa of a and fb of b cross. */
static int meshes_meet(const double *ga, const double *gb, int n)
{
    for (int i = 0; i + 1 < n; i++)
        for (int j = 0; j + 1 < n; j++)
            for (int h = 0; h < 2; h++) {
                const double *s[3] = {ga + 3 * (i * n + j), ga + 3 * ((i + 1) * n + j + h),
                                      ga + 3 * ((i + h) * n + j + 1)};
                cb_aabb bs;
                double pts[9];
                for (int k = 0; k < 3; k++)
                    memcpy(pts + 3 * k, s[k], sizeof(double) * 3);
                cb_aabb_of_points(&bs, pts, 3, 3);
                for (int k = 0; k + 1 < n; k++)
                    for (int l = 0; l + 1 < n; l++)
                        for (int g = 0; g < 2; g++) {
                            const double *t[3] = {gb + 3 * (k * n + l),
                                                  gb + 3 * ((k + 1) * n + l + g),
                                                  gb + 3 * ((k + g) * n + l + 1)};
                            cb_aabb bt;
                            double qts[9];
                            for (int c = 0; c < 3; c++)
                                memcpy(qts + 3 * c, t[c], sizeof(double) * 3);
                            cb_aabb_of_points(&bt, qts, 3, 3);
                            if (cb_aabb_overlap(&bs, &bt, 0) && triangles_meet(s, t))
                                return 1;
                        }
            }
    return 0;
}

static void test_overlap(void)
{
    cb_hummingbird_params pa, pb;
    cb_hummingbird_params_default(&pa);
    fig12_pose(&pb);
    cb_topo_body *a = make_bird(&pa), *b = make_bird(&pb);
    if (a && b) {
        cb_aabb ba, bb;
        cb_topo_body_edge_box(&ba, a);
        cb_topo_body_edge_box(&bb, b);
        CHECK(cb_aabb_overlap(&ba, &bb, 0), "the birds' boxes do not meet");
        enum { GRID = 9 };
        double *ga = malloc(sizeof *ga * 3 * GRID * GRID * (size_t)a->n_faces);
        double *gb = malloc(sizeof *gb * 3 * GRID * GRID * (size_t)b->n_faces);
        for (int f = 0; f < a->n_faces; f++)
            for (int i = 0; i < GRID; i++)
                for (int j = 0; j < GRID; j++) {
                    face_point(ga + 3 * ((size_t)f * GRID * GRID + i * GRID + j), a, f, i, j, GRID);
                    face_point(gb + 3 * ((size_t)f * GRID * GRID + i * GRID + j), b, f, i, j, GRID);
                }
        int boxes = 0, crossing = 0;
        for (int f = 0; f < a->n_faces; f++)
            for (int g = 0; g < b->n_faces; g++) {
                cb_aabb fa, fb;
                net_box(&fa, a, f);
                net_box(&fb, b, g);
                if (!cb_aabb_overlap(&fa, &fb, 0))
                    continue;
                boxes++;
                crossing += meshes_meet(ga + 3 * (size_t)f * GRID * GRID,
                                        gb + 3 * (size_t)g * GRID * GRID, GRID);
            }
        printf("two birds: %d face pairs with overlapping control-net boxes, %d whose %d x %d "
               "meshes cross (the paper's Fig. 12: 99 intersecting pairs)\n",
               boxes, crossing, GRID - 1, GRID - 1);
        CHECK(crossing >= 50 && crossing <= 200, "%d crossing face pairs, about 100 wanted",
              crossing);
        free(ga);
        free(gb);
    }
    cb_topo_body_free(a);
    cb_topo_body_free(b);
}

static void test_bad_params(void)
{
    cb_hummingbird_params p;
    cb_topo_body *b = (cb_topo_body *)&p;
    cb_error err;
    cb_hummingbird_params_default(&p);
    p.scale = 0;
    CHECK(cb_model_hummingbird(&b, &p, &err) == CB_ERR_INVALID && !b && strstr(err.msg, "scale"),
          "scale 0: '%s'", err.msg);
    cb_hummingbird_params_default(&p);
    p.wing_angle_deg = 80;
    CHECK(cb_model_hummingbird(&b, &p, &err) == CB_ERR_INVALID && !b &&
              strstr(err.msg, "wing angle"),
          "wing angle 80: '%s'", err.msg);
    cb_hummingbird_params_default(&p);
    p.axis[2] = 0;
    p.angle_deg = 10;
    CHECK(cb_model_hummingbird(&b, &p, &err) == CB_ERR_INVALID && !b && strstr(err.msg, "axis"),
          "zero axis: '%s'", err.msg);
    /* Every accepted wing angle gives a valid bird. */
    for (int w = -30; w <= 50; w += 40) {
        cb_hummingbird_params_default(&p);
        p.wing_angle_deg = w;
        cb_topo_body *c = make_bird(&p);
        if (c) {
            char what[64];
            snprintf(what, sizeof what, "hummingbird, wing angle %d", w);
            check_valid(c, what);
            CHECK(volume_exact(c) > 0, "wing angle %d: volume %g", w, volume_exact(c));
        }
        cb_topo_body_free(c);
    }
}

/* ---------------------------------------------------------------- command ------------------ */

/* ---------------------------------------------------------------- volume estimate ---------- */

static cb_topo_body *unit_sphere(double cx, int as_nurbs)
{
    cb_frame f;
    cb_error err;
    double c[3] = {cx, 0, 0}, z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    cb_topo_body *b = NULL;
    cb_status st = cb_frame_make(&f, c, z, x, &err);
    if (!st)
        st = cb_prim_sphere(&b, &f, 1, as_nurbs, 0, &err);
    CHECK(st == CB_OK, "sphere: %s", err.msg);
    return b;
}

/* Two unit spheres one apart: V = 4 pi / 3 each, their lens 5 pi / 12. The estimate must land
 * within four of its standard deviations, which must be small; the same numbers on 1 and 2
 * threads; bad grid sizes refused. */
static void test_estimate_spheres(void)
{
    for (int nurbs = 0; nurbs < 2; nurbs++) {
        cb_topo_body *a = unit_sphere(0, nurbs), *b = unit_sphere(1, nurbs);
        if (!a || !b) {
            cb_topo_body_free(a);
            cb_topo_body_free(b);
            return;
        }
        cb_overlap_estimate e, e1;
        cb_error err;
        cb_status st = cb_model_overlap_estimate(&e, a, b, 60, 2, &err);
        CHECK(st == CB_OK, "sphere estimate: %s", err.msg);
        double ball = 4 * PI / 3, lens = 5 * PI / 12;
        if (!st) {
            CHECK(fabs(e.volume_a - ball) <= 4 * e.sigma_a && e.sigma_a < 0.01 * ball,
                  "sphere A: %.6g +- %.2g, exact %.6g", e.volume_a, e.sigma_a, ball);
            CHECK(fabs(e.volume_b - ball) <= 4 * e.sigma_b && e.sigma_b < 0.01 * ball,
                  "sphere B: %.6g +- %.2g, exact %.6g", e.volume_b, e.sigma_b, ball);
            CHECK(fabs(e.volume_ab - lens) <= 4 * e.sigma_ab && e.sigma_ab < 0.01 * lens,
                  "lens: %.6g +- %.2g, exact %.6g", e.volume_ab, e.sigma_ab, lens);
            printf("estimate, %s spheres, 60 x 60 lines: lens %.6f +- %.1e (exact %.6f), %ld "
                   "lines drawn again\n",
                   nurbs ? "NURBS" : "analytic", e.volume_ab, e.sigma_ab, lens, e.retries);
        }
        st = cb_model_overlap_estimate(&e1, a, b, 60, 1, &err);
        CHECK(st == CB_OK && !memcmp(&e, &e1, sizeof e), "estimate differs on 1 and 2 threads");
        CHECK(cb_model_overlap_estimate(&e1, a, b, 7, 1, &err) == CB_ERR_INVALID &&
                  strstr(err.msg, "grid size 7"),
              "odd grid: %s", err.msg);
        CHECK(cb_model_overlap_estimate(&e1, a, b, 0, 1, &err) == CB_ERR_INVALID, "grid 0 taken");
        cb_topo_body_free(a);
        cb_topo_body_free(b);
    }
}

/* The two birds of the Boolean scenario: a coarse estimate agrees with the B-rep volumes of
 * brep/mass.h and with the stored reference (cb_hummingbird_pair_reference) within four
 * standard deviations of their difference. */
static void test_estimate_birds(void)
{
    cb_hummingbird_params pa, pb;
    cb_hummingbird_pair(&pa, &pb);
    cb_topo_body *a = make_bird(&pa), *b = make_bird(&pb);
    cb_error err;
    if (a && b && !cb_topo_compute_pcurves(a, a->tol, &err) &&
        !cb_topo_compute_pcurves(b, b->tol, &err)) {
        cb_overlap_estimate e;
        cb_mass_props ma, mb;
        cb_status st = cb_model_overlap_estimate(&e, a, b, 200, 0, &err);
        if (!st)
            st = cb_mass_body(&ma, a, 1e-10, NULL, &err);
        if (!st)
            st = cb_mass_body(&mb, b, 1e-10, NULL, &err);
        CHECK(st == CB_OK, "birds estimate: %s", err.msg);
        if (!st) {
            const cb_overlap_estimate *r = &cb_hummingbird_pair_reference;
            CHECK(fabs(e.volume_a - ma.volume) <= 4 * e.sigma_a, "V(A): estimate %.8g +- %.2g, "
                  "B-rep %.10g", e.volume_a, e.sigma_a, ma.volume);
            CHECK(fabs(e.volume_b - mb.volume) <= 4 * e.sigma_b, "V(B): estimate %.8g +- %.2g, "
                  "B-rep %.10g", e.volume_b, e.sigma_b, mb.volume);
            CHECK(fabs(r->volume_a - ma.volume) <= 4 * r->sigma_a &&
                      fabs(r->volume_b - mb.volume) <= 4 * r->sigma_b,
                  "reference V(A) %.10g, V(B) %.10g; B-rep %.10g, %.10g", r->volume_a,
                  r->volume_b, ma.volume, mb.volume);
            double sd = sqrt(e.sigma_ab * e.sigma_ab + r->sigma_ab * r->sigma_ab);
            CHECK(fabs(e.volume_ab - r->volume_ab) <= 4 * sd,
                  "V(A n B): estimate %.8g +- %.2g, reference %.10g +- %.2g", e.volume_ab,
                  e.sigma_ab, r->volume_ab, r->sigma_ab);
            printf("birds, 200 x 200 lines: V(A) %.7f +- %.1e (B-rep %.9f), V(A n B) %.7f +- "
                   "%.1e (reference %.9f +- %.1e)\n",
                   e.volume_a, e.sigma_a, ma.volume, e.volume_ab, e.sigma_ab, r->volume_ab,
                   r->sigma_ab);
        }
    }
    cb_topo_body_free(a);
    cb_topo_body_free(b);
}

/* The bracket: counts, validity, the closed-form volume against the B-rep integration,
 * analytic and NURBS, posed; bad shapes refused. */
static void test_bracket(void)
{
    for (int nurbs = 0; nurbs < 2; nurbs++) {
        cb_bracket_params p;
        cb_bracket_params_default(&p);
        p.as_nurbs = nurbs;
        p.pose.axis[0] = 1;
        p.pose.angle_deg = 25;
        p.pose.translate[1] = 3;
        cb_topo_body *b = NULL;
        cb_error err;
        cb_status st = cb_model_bracket(&b, &p, &err);
        CHECK(st == CB_OK, "bracket: %s", err.msg);
        if (st)
            continue;
        CHECK(b->n_faces == 11 && b->n_edges == 27 && b->n_vertices == 18 && b->n_solids == 1,
              "bracket: %d faces, %d edges, %d vertices", b->n_faces, b->n_edges, b->n_vertices);
        check_valid(b, nurbs ? "bracket NURBS" : "bracket");
        cb_mass_props m;
        double v = cb_bracket_volume(&p.shape);
        CHECK(!cb_mass_body(&m, b, 1e-12, NULL, &err) && fabs(m.volume - v) <= 1e-9 * v,
              "bracket volume %.15g, closed form %.15g", m.volume, v);
        cb_topo_body_free(b);
    }
    cb_bracket_params p;
    cb_bracket_params_default(&p);
    p.shape.hole_x = 1.1; /* the hole would cut the fillet */
    cb_topo_body *b = NULL;
    cb_error err;
    CHECK(cb_model_bracket(&b, &p, &err) == CB_ERR_INVALID && !b && strstr(err.msg, "hole"),
          "bad bracket: %s", err.msg);
    cli_expect("model bracket -o /nonexistent/dir/b.step", 2, "cannot create");
    cli_expect("model bracket -o x.step --fillet 1", 2, "--fillet does not apply to bracket");
}

/* The scenario list the demo and the benchmarks share: names, bad indices, references. */
static void test_scenarios(void)
{
    int n = cb_model_scenario_count();
    CHECK(n == 1 + 2 * cb_cardan_scenario_count() + 4, "%d scenarios", n);
    char name[64];
    cb_error err;
    CHECK(!cb_model_scenario_name(name, sizeof name, 0, &err) && !strcmp(name, "hummingbirds"),
          "scenario 0: %s", name);
    CHECK(!cb_model_scenario_name(name, sizeof name, n - 1, &err) &&
              strstr(name, "_nurbs") != NULL,
          "last scenario: %s", name);
    CHECK(cb_model_scenario_name(name, sizeof name, n, &err) == CB_ERR_INVALID, "index %d taken",
          n);
    cb_model_scenario s;
    CHECK(cb_model_scenario_load(&s, -1, &err) == CB_ERR_INVALID && !s.a && !s.b,
          "index -1 loaded");
    cb_status st = cb_model_scenario_load(&s, 1 + cb_cardan_scenario_count(), &err);
    CHECK(st == CB_OK && s.a && s.b, "first NURBS scenario: %s", err.msg);
    if (!st) {
        cb_cardan_scenario c;
        cb_cardan_volumes v;
        cb_cardan_scenario_get(&c, 0, &err);
        cb_cardan_scenario_volumes(&v, &c, &err);
        CHECK(s.ref[0] == v.a_union_b && s.ref[1] == v.a_inter_b && s.ref[2] == v.a_minus_b,
              "%s: references", s.name);
        CHECK(s.a->surfaces[0].kind == CB_SURFACE_NURBS, "%s: faces not B-splines", s.name);
        CHECK(fabs(s.bar[0] - (1e-6 * v.a_union_b + 1e-9 * (v.a + v.b))) <= 1e-15 * v.a_union_b,
              "%s: bar %g", s.name, s.bar[0]);
    }
    cb_model_scenario_clear(&s);
}

/* The paper's Example 2 pair: both B-splines equal the appendix's rational polynomials on a
 * grid of their domains (P of Example 1 on [0, 1]^2, Q on [-1, 1] x [0, 2]), and their
 * homogeneous control points are integers. */
static void test_paper_example2(void)
{
    cb_nurbs_surface_t P, Q;
    cb_nurbs_surface_init(P);
    cb_nurbs_surface_init(Q);
    cb_error err;
    cb_status st = cb_model_paper_example2(P, Q, &err);
    CHECK(st == CB_OK, "example 2: %s", err.msg);
    double worst = 0;
    int integral = 1;
    for (int k = 0; k < 16 * 4 && st == CB_OK; k++)
        integral &= P->cw[k] == floor(P->cw[k]) && Q->cw[k] == floor(Q->cw[k]);
    for (int i = 0; i <= 8 && st == CB_OK; i++)
        for (int j = 0; j <= 8; j++) {
            double s = i / 8.0, t = j / 8.0, X[3], Y[3];
            cb_nurbs_surface_eval(X, P, s, t);
            double pw = 2;
            double px[3] = {-32 * s * s * s + 96 * s * t * t + 48 * s * s - 96 * s * t -
                                48 * t * t + 6 * s + 48 * t - 11,
                            96 * s * s * t - 32 * t * t * t - 48 * s * s - 96 * s * t +
                                48 * t * t + 48 * s + 6 * t - 11,
                            24 * s * s - 24 * t * t - 24 * s + 24 * t};
            s = -1 + 2 * s;
            t = 2 * t;
            cb_nurbs_surface_eval(Y, Q, s, t);
            double w = s * s * t * t + s * s + t * t + 1;
            double qx[3] = {2 * s * t * t + 2 * s, -s * s * t * t * t + s * s - 3 * t * t * t + 3,
                            2 * s * s * s * t + 6 * t};
            for (int q = 0; q < 3; q++) {
                worst = fmax(worst, fabs(X[q] - px[q] / pw));
                worst = fmax(worst, fabs(Y[q] - qx[q] / w));
            }
        }
    CHECK(worst < 1e-12 && integral, "example 2: off the appendix's surfaces by %g, integral %d",
          worst, integral);
    cb_nurbs_surface_clear(P);
    cb_nurbs_surface_clear(Q);
}

static void test_command(void)
{
    char path[256], args[512];
    snprintf(path, sizeof path, "/tmp/colibri_model_%d.step", (int)getpid());
    cli_expect("model --help", 0, "usage: colibri model NAME");
    cli_expect("model", 2, "usage: colibri model NAME");
    cli_expect("model hummingbird", 2, "usage: colibri model NAME");
    snprintf(args, sizeof args, "model sparrow -o %s", path);
    cli_expect(args, 2, "unknown model 'sparrow'");
    snprintf(args, sizeof args, "model hummingbird -o %s --scale -1", path);
    cli_expect(args, 2, "--scale");
    snprintf(args, sizeof args, "model hummingbird -o %s --rotate 0 0 1", path);
    cli_expect(args, 2, "--rotate");
    cli_expect("model hummingbird -o /nonexistent/dir/bird.step", 2, "cannot create");
    cli_expect("model hummingbird-pair --estimate 7", 2, "--estimate");
    cli_expect("model hummingbird-pair", 2, "usage: colibri model NAME");
    cli_expect("model hummingbird-pair --estimate 20 --rotate 0 0 1 5", 2,
               "--rotate does not apply to hummingbird-pair");
    snprintf(args, sizeof args, "model hummingbird -o %s --estimate 20", path);
    cli_expect(args, 2, "--estimate does not apply");
    cli_expect("model hummingbird-pair --estimate 20 --threads 1", 0, "V(A n B) 0.5");
    snprintf(args, sizeof args,
             "model hummingbird -o %s --scale 2 --rotate 0.2 0.3 1 40 --translate 0.8 0.5 0.3 "
             "--wing-angle 5",
             path);
    cli_expect(args, 0, "312 faces, 624 edges, 314 vertices");
    cli_expect(args, 0, "valid");
    snprintf(args, sizeof args, "info %s", path);
    cli_expect(args, 0, "1 solid, 1 shell, 312 faces, 624 edges, 314 vertices");
    cli_expect(args, 0, "bspline 312");
    remove(path);
}

/* Graph pairs: Q minus P is S h / 2^j along the rotated z axis over every (x, y) of the
 * square, reached through Q's own parameters; P is the lifted square; P and Q have their one
 * interior knot per direction; an overflowing h and one too long for doubles are refused. */
static void test_graph_pair(void)
{
    cb_model_poly a = cb_model_poly_circle(4, 2, 2, 1), b = cb_model_poly_linear(3, -2, 1);
    cb_model_poly h = cb_model_poly_mul(&a, &b);
    CHECK(cb_model_poly_eval(&h, 0.5, 0.25) == 0 && cb_model_poly_eval(&h, 1, 2) == 0,
          "graph pair: h vanishes on its circle and line");
    cb_nurbs_surface_t P, Q;
    cb_nurbs_surface_init(P);
    cb_nurbs_surface_init(Q);
    cb_model_graph g;
    cb_error err;
    cb_status st = cb_model_graph_pair(P, Q, &g, &h, &err);
    CHECK(st == CB_OK, "graph pair: %s", err.msg);
    if (st == CB_OK) {
        CHECK(P->deg_u == 2 && P->deg_v == 2 && P->n_u == 4 && P->n_v == 4 && Q->deg_u == 3 &&
                  Q->deg_v == 3 && Q->n_u == 5 && Q->n_v == 5,
              "graph pair: degrees (%d %d) (%d %d), nets %d x %d, %d x %d", P->deg_u, P->deg_v,
              Q->deg_u, Q->deg_v, P->n_u, P->n_v, Q->n_u, Q->n_v);
        double worst = 0;
        for (int i = 0; i <= 10; i++)
            for (int j = 0; j <= 10; j++) {
                double x = i / 10.0, y = j / 10.0, XP[3], XQ[3], XT[3];
                cb_nurbs_surface_eval(XP, P, x, y);
                cb_nurbs_surface_eval(XQ, Q, 2 * (1 - y), 2 * x - 1);
                cb_model_graph_point(XT, &g, x, y);
                double dz = g.scale * cb_model_poly_eval(&h, x, y) / ldexp(1, g.height_shift);
                /* The motion takes z to the first coordinate, x to the second, y to the third. */
                double e[6] = {XQ[0] - XP[0] - dz, XQ[1] - XP[1], XQ[2] - XP[2],
                               XP[0] - XT[0], XP[1] - XT[1], XP[2] - XT[2]};
                for (int k = 0; k < 6; k++)
                    worst = fmax(worst, fabs(e[k]));
                if (i == 3 && j == 7)
                    CHECK(fabs(XP[1] - 0.3 * g.scale + 1.25) < 1e-15 &&
                              fabs(XP[2] - 0.7 * g.scale - 0.5) < 1e-15,
                          "graph pair: P over (0.3, 0.7) at (%g, %g)", XP[1], XP[2]);
            }
        CHECK(worst < 1e-14, "graph pair: Q - P off S h / 2^j by %g", worst);
        CHECK(g.scale >= 0.5 && g.scale < 1, "graph pair: scale %g", g.scale);
    }
    cb_model_poly big = cb_model_poly_linear(1LL << 26, 0, 1);
    cb_model_poly big2 = cb_model_poly_mul(&big, &big);
    cb_model_poly huge = cb_model_poly_mul(&big2, &big2);
    CHECK(!big2.overflow && huge.overflow, "graph pair: 2^104 overflows, 2^52 does not");
    st = cb_model_graph_pair(P, Q, &g, &huge, &err);
    CHECK(st == CB_ERR_INVALID && strstr(err.msg, "overflow"), "graph pair: overflow: %s",
          err.msg);
    st = cb_model_graph_pair(P, Q, &g, &big2, &err);
    CHECK(st == CB_ERR_INVALID && strstr(err.msg, "exact"), "graph pair: long h: %s", err.msg);
    cb_nurbs_surface_clear(P);
    cb_nurbs_surface_clear(Q);
}

int main(void)
{
    double t0 = seconds();
    test_default();
    test_pose();
    test_step_round_trip();
    test_overlap();
    test_bad_params();
    test_estimate_spheres();
    test_estimate_birds();
    test_scenarios();
    test_bracket();
    test_command();
    test_paper_example2();
    test_graph_pair();
    printf("models tests: %.2f s\n", seconds() - t0);
    return check_report("models");
}
