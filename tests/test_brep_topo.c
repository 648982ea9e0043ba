/* Topology and its geometry (brep/topo*.c): evaluation identities, nearest points, a body built
 * by hand, the queries, and the validator finding each kind of defect. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/prim.h"
#include "brep/topo.h"
#include "check.h"

static const double PI = 3.14159265358979323846;

static void random_frame(cb_frame *f, check_rng *rng)
{
    double o[3], z[3], x[3];
    for (int k = 0; k < 3; k++) {
        o[k] = check_rng_uniform(rng, -5, 5);
        z[k] = check_rng_uniform(rng, -1, 1);
        x[k] = check_rng_uniform(rng, -1, 1);
    }
    if (cb_frame_make(f, o, z, x, NULL)) {
        double zz[3] = {0, 0, 1};
        cb_frame_make(f, o, zz, NULL, NULL);
    }
}

/* Unit normal of s at (u, v). */
static void normal_at(double n[3], double p[3], const cb_topo_surface *s, double u, double v)
{
    double d[6][3];
    cb_topo_surface_eval_derivs(d, s, u, v);
    cb_vec3_cross(n, d[1], d[2]);
    cb_vec3_normalize(n);
    memcpy(p, d[0], sizeof d[0]);
}

/* Derivatives of every surface kind against central differences. */
static void check_derivs(const cb_topo_surface *s, const char *what, double u, double v)
{
    double d[6][3], a[6][3], b[6][3], h = 1e-5;
    cb_topo_surface_eval_derivs(d, s, u, v);
    cb_topo_surface_eval_derivs(a, s, u + h, v);
    cb_topo_surface_eval_derivs(b, s, u - h, v);
    double err = 0;
    for (int i = 0; i < 3; i++) {
        err = fmax(err, fabs((a[0][i] - b[0][i]) / (2 * h) - d[1][i]));
        err = fmax(err, fabs((a[1][i] - b[1][i]) / (2 * h) - d[3][i]));
        err = fmax(err, fabs((a[2][i] - b[2][i]) / (2 * h) - d[4][i]));
    }
    cb_topo_surface_eval_derivs(a, s, u, v + h);
    cb_topo_surface_eval_derivs(b, s, u, v - h);
    for (int i = 0; i < 3; i++) {
        err = fmax(err, fabs((a[0][i] - b[0][i]) / (2 * h) - d[2][i]));
        err = fmax(err, fabs((a[2][i] - b[2][i]) / (2 * h) - d[5][i]));
    }
    CHECK(err < 1e-5, "%s: derivatives off by %g at (%g, %g)", what, err, u, v);
}

/* Points moved a known distance along the normal must measure that distance (for offsets
 * below the smallest radius of curvature). */
static void check_distance(const cb_topo_surface *s, const char *what, double u0, double u1,
                           double v0, double v1, double max_off, check_rng *rng)
{
    cb_topo_projector pr;
    cb_error err;
    CHECK(cb_topo_projector_init(&pr, s, &err) == CB_OK, "%s: %s", what, err.msg);
    double worst = 0;
    for (int trial = 0; trial < 100; trial++) {
        double u = check_rng_uniform(rng, u0, u1), v = check_rng_uniform(rng, v0, v1);
        double off = check_rng_uniform(rng, -max_off, max_off), n[3], p[3];
        normal_at(n, p, s, u, v);
        for (int i = 0; i < 3; i++)
            p[i] += off * n[i];
        double d = cb_topo_projector_distance(&pr, p);
        worst = fmax(worst, fabs(d - fabs(off)));
        check_derivs(s, what, u, v);
    }
    CHECK(worst < 1e-9, "%s: distance off by %g", what, worst);
    cb_topo_projector_clear(&pr);
}

/* Points of the surface over its whole parameter box come back from the global inversion
 * (no guess) onto themselves: any (u, v) of the point will do. */
static void check_inversion(const cb_topo_surface *s, const char *what, check_rng *rng)
{
    cb_topo_inverter inv;
    cb_error err;
    CHECK(cb_topo_inverter_init(&inv, s, 1e-9, &err) == CB_OK, "%s: %s", what, err.msg);
    double worst = 0;
    for (int trial = 0; trial < 200; trial++) {
        double u = check_rng_uniform(rng, 0, 2 * PI), v = check_rng_uniform(rng, 0, 2 * PI);
        double p[3], q[3], uv[2];
        cb_topo_inverter_eval(p, &inv, u, v);
        cb_topo_inverter_invert(uv, &inv, p, NULL);
        cb_topo_inverter_eval(q, &inv, uv[0], uv[1]);
        worst = fmax(worst, cb_vec3_dist(p, q));
    }
    CHECK(worst < 1e-9, "%s: inverted points off by %g", what, worst);
    cb_topo_inverter_clear(&inv);
}

static void test_surfaces(void)
{
    check_rng rng = {7};
    cb_error err;
    for (int trial = 0; trial < 5; trial++) {
        cb_frame f;
        random_frame(&f, &rng);
        cb_topo_surface s;
        cb_topo_surface_init(&s);
        s.kind = CB_SURFACE_ANALYTIC;
        cb_analytic_plane(&s.analytic, &f, &err);
        check_distance(&s, "plane", -3, 3, -3, 3, 1.0, &rng);
        cb_analytic_cylinder(&s.analytic, &f, 2.0, &err);
        check_distance(&s, "cylinder", 0, 2 * PI, -3, 3, 1.0, &rng);
        cb_analytic_cone(&s.analytic, &f, 1.0, 0.4, &err);
        check_distance(&s, "cone", 0, 2 * PI, 0, 3, 0.3, &rng);
        cb_analytic_sphere(&s.analytic, &f, 2.0, &err);
        check_distance(&s, "sphere", 0, 2 * PI, -1.4, 1.4, 1.0, &rng);
        cb_analytic_torus(&s.analytic, &f, 3.0, 1.0, &err);
        check_distance(&s, "torus", 0, 2 * PI, 0, 2 * PI, 0.5, &rng);
        /* A spindle torus (R < r: a screw head's dome, r0901_ec.stp): its apple (the outer
         * part, R + r cos v > 0, |v| < 2.094 here) and its lemon (inside, across the axis
         * from its tube circle). Both measured against the nearer tube circle. */
        CHECK(cb_analytic_torus(&s.analytic, &f, 1.0, 2.0, &err) == CB_OK, "spindle torus: %s",
              err.msg);
        check_distance(&s, "spindle torus, apple", 0, 2 * PI, -1.5, 1.5, 0.3, &rng);
        check_distance(&s, "spindle torus, lemon", 0, 2 * PI, 2.7, 3.58, 0.2, &rng);
        check_inversion(&s, "spindle torus", &rng);

        /* The same sphere as an exact rational B-spline, and as a circle revolved. */
        cb_analytic_sphere(&s.analytic, &f, 2.0, &err);
        cb_topo_surface n;
        cb_topo_surface_init(&n);
        n.kind = CB_SURFACE_NURBS;
        CHECK(cb_analytic_to_nurbs(n.nurbs, &s.analytic, 0, 2 * PI, -1.3, 1.3, &err) == CB_OK, "%s",
              err.msg);
        double box[4];
        cb_nurbs_surface_domain(n.nurbs, box);
        check_distance(&n, "nurbs sphere", box[0], box[1], box[2], box[3], 0.5, &rng);
        cb_topo_surface_clear(&n);

        cb_topo_surface r;
        cb_topo_surface_init(&r);
        r.kind = CB_SURFACE_REVOLUTION;
        r.frame = f;
        r.profile.kind = CB_CURVE_CIRCLE;
        r.profile.r1 = r.profile.r2 = 1.0;
        /* Profile: the unit circle about o + 3 x' in the x'z' plane, so a torus (3, 1). */
        double c[3] = {3, 0, 0}, minus_y[3] = {-f.y[0], -f.y[1], -f.y[2]};
        cb_frame_to_world(c, &f, c);
        cb_frame_make(&r.profile.frame, c, minus_y, f.x, &err);
        check_distance(&r, "revolution", 0, 2 * PI, 0, 2 * PI, 0.5, &rng);
        cb_topo_surface_clear(&r);

        cb_topo_surface e;
        cb_topo_surface_init(&e);
        e.kind = CB_SURFACE_EXTRUSION;
        e.profile.kind = CB_CURVE_ELLIPSE;
        e.profile.frame = f;
        e.profile.r1 = 2.0;
        e.profile.r2 = 1.0;
        for (int k = 0; k < 3; k++)
            e.dir[k] = 1.5 * f.z[k];
        check_distance(&e, "extrusion", 0, 2 * PI, -2, 2, 0.3, &rng);
        cb_topo_surface_clear(&e);
        cb_topo_surface_clear(&s);
    }
}

static void test_curves(void)
{
    check_rng rng = {11};
    cb_error err;
    for (int trial = 0; trial < 50; trial++) {
        cb_topo_curve c;
        cb_topo_curve_init(&c);
        random_frame(&c.frame, &rng);
        int kind = trial % 4;
        c.kind = (cb_curve_kind)kind;
        c.r1 = check_rng_uniform(&rng, 0.5, 3);
        c.r2 = kind == CB_CURVE_ELLIPSE ? check_rng_uniform(&rng, 0.5, 3) : c.r1;
        double a = 0, b = 2 * PI;
        if (kind == CB_CURVE_NURBS) {
            double z[3] = {c.frame.z[0], c.frame.z[1], c.frame.z[2]};
            CHECK(cb_nurbs_curve_arc(c.nurbs, c.frame.o, c.frame.x, z, c.r1, 0.2, 2.5, &err) ==
                      CB_OK,
                  "%s", err.msg);
            a = 0.2;
            b = 2.5;
        }
        double t = check_rng_uniform(&rng, a + 0.1, b - 0.1), d[3][3], e1[3][3], e2[3][3], h = 1e-6;
        cb_topo_curve_eval_derivs(d, &c, t);
        cb_topo_curve_eval_derivs(e1, &c, t + h);
        cb_topo_curve_eval_derivs(e2, &c, t - h);
        double worst = 0;
        for (int i = 0; i < 3; i++) {
            worst = fmax(worst, fabs((e1[0][i] - e2[0][i]) / (2 * h) - d[1][i]));
            worst = fmax(worst, fabs((e1[1][i] - e2[1][i]) / (2 * h) - d[2][i]));
        }
        CHECK(worst < 1e-6, "%s: derivatives off by %g", cb_curve_kind_name(c.kind), worst);
        /* Projecting a curve point gives back its parameter (modulo the period). */
        double tp, dist = cb_topo_curve_project(&tp, &c, d[0], a, b);
        double dt = fabs(tp - t);
        if (kind == CB_CURVE_CIRCLE || kind == CB_CURVE_ELLIPSE)
            dt = fmin(dt, fabs(dt - 2 * PI));
        CHECK(dist < 1e-12 && dt < 1e-7, "%s: projection t %g -> %g, distance %g",
              cb_curve_kind_name(c.kind), t, tp, dist);
        /* Rigid motions commute with evaluation. */
        cb_xform x;
        double axis[3] = {1, 2, 3}, pt[3] = {0.5, -1, 2}, q[3], r[3];
        cb_xform_rotation(&x, pt, axis, 0.7);
        cb_xform_apply_point(q, &x, d[0]);
        cb_topo_curve_transform(&c, &x);
        cb_topo_curve_eval(r, &c, t);
        CHECK(cb_vec3_dist(q, r) < 1e-12, "%s: transform", cb_curve_kind_name(c.kind));
        cb_topo_curve_clear(&c);
    }
}

/* ---------------------------------------------------------------- a body by hand ----------- */

/* A tetrahedron with planar faces and line edges: 4 vertices, 6 edges, and its first n_faces
 * faces (4 for the closed solid). */
static cb_topo_body *tetrahedron(int n_faces)
{
    static const double P[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    /* Faces as vertex cycles, counterclockwise seen from outside. */
    static const int F[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    cb_topo_body *b = cb_topo_body_new();
    cb_error err;
    for (int k = 0; k < 4; k++) {
        int v = cb_topo_body_add_vertex(b);
        memcpy(b->vertices[v].p, P[k], sizeof P[k]);
    }
    int edge[4][4];
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++) {
            int e = cb_topo_body_add_edge(b), c = cb_topo_body_add_curve(b);
            double d[3] = {P[j][0] - P[i][0], P[j][1] - P[i][1], P[j][2] - P[i][2]};
            cb_topo_curve *cv = &b->curves[c];
            cv->kind = CB_CURVE_LINE;
            cv->r1 = cb_vec3_norm(d);
            cb_frame_make(&cv->frame, P[i], d, NULL, &err);
            b->edges[e] = (cb_topo_edge){
                .curve = c, .t0 = 0, .t1 = 1, .same_sense = 1, .v = {i, j}, .tol = 1e-9};
            edge[i][j] = edge[j][i] = e;
        }
    int sh = cb_topo_body_add_shell(b), so = cb_topo_body_add_solid(b);
    b->solids[so] = (cb_topo_solid){.first = sh, .count = 1};
    b->shells[sh] = (cb_topo_shell){.first = 0, .count = n_faces, .closed = 1, .solid = so};
    for (int f = 0; f < n_faces; f++) {
        int fi = cb_topo_body_add_face(b), s = cb_topo_body_add_surface(b),
            l = cb_topo_body_add_loop(b);
        const double *a = P[F[f][0]], *p1 = P[F[f][1]], *p2 = P[F[f][2]];
        double u[3], w[3], n[3];
        for (int k = 0; k < 3; k++) {
            u[k] = p1[k] - a[k];
            w[k] = p2[k] - a[k];
        }
        cb_vec3_cross(n, u, w);
        cb_frame fr;
        cb_frame_make(&fr, a, n, u, &err);
        b->surfaces[s].kind = CB_SURFACE_ANALYTIC;
        cb_analytic_plane(&b->surfaces[s].analytic, &fr, &err);
        b->faces[fi] =
            (cb_topo_face){.surface = s, .same_sense = 1, .first = l, .count = 1, .shell = sh};
        b->loops[l] = (cb_topo_loop){.first = b->n_coedges, .count = 3, .outer = 1, .face = fi};
        for (int k = 0; k < 3; k++) {
            int from = F[f][k], to = F[f][(k + 1) % 3], c = cb_topo_body_add_coedge(b);
            b->coedges[c] = (cb_topo_coedge){
                .edge = edge[from][to], .sense = from < to, .pcurve = -1, .loop = l};
        }
    }
    b->tol = 1e-9;
    return b;
}

/* Validates b and returns 1 when some problem contains `what`. */
static int reports(cb_topo_body *b, const char *what, int *n_problems)
{
    cb_topo_report r;
    cb_topo_report_init(&r);
    cb_error err;
    CHECK(cb_topo_validate(&r, b, 0, 7, &err) == CB_OK, "validate: %s", err.msg);
    int found = 0;
    for (int k = 0; k < r.n; k++)
        found |= what && strstr(r.items[k], what) != NULL;
    if (n_problems)
        *n_problems = r.n;
    cb_topo_report_clear(&r);
    return found;
}

static void test_body(void)
{
    cb_topo_body *b = tetrahedron(4);
    cb_error err;
    int n;
    CHECK(cb_topo_body_index(b, &err) == CB_OK, "index: %s", err.msg);
    reports(b, NULL, &n);
    CHECK(n == 0, "tetrahedron: %d problems", n);

    int out[8];
    for (int f = 0; f < 4; f++) {
        CHECK(cb_topo_face_neighbours(out, 8, b, f) == 3, "face %d: not 3 neighbours", f);
        for (int k = 0; k < 3; k++)
            CHECK(out[k] != f, "face %d is its own neighbour", f);
    }
    for (int v = 0; v < 4; v++)
        CHECK(cb_topo_vertex_edges(out, 8, b, v) == 3, "vertex %d: not 3 edges", v);
    for (int e = 0; e < 6; e++) {
        CHECK(cb_topo_edge_faces(out, 8, b, e) == 2 && out[0] < out[1], "edge %d faces", e);
        CHECK(cb_topo_edge_faces(out, 0, b, e) == 2, "edge %d: sizing call", e);
    }
    const char *names[8];
    int counts[8];
    CHECK(cb_topo_body_surface_types(names, counts, b) == 1 && !strcmp(names[0], "plane") &&
              counts[0] == 4,
          "surface types");

    /* One defect at a time, each named by the validator. */
    b->edges[0].t1 = 0.5;
    CHECK(reports(b, "from vertex", NULL), "short edge not reported");
    b->edges[0].t1 = 1.0;
    b->coedges[0].sense ^= 1;
    CHECK(reports(b, "both coedges run", NULL) && reports(b, "is open", NULL),
          "reversed coedge not reported");
    b->coedges[0].sense ^= 1;
    b->surfaces[0].analytic.frame.o[2] -= 1e-3; /* face 0 is the plane z = 0 */
    CHECK(reports(b, "off the plane surface of face 0", NULL), "moved plane not reported");
    b->surfaces[0].analytic.frame.o[2] += 1e-3;
    b->edges[2].t1 = b->edges[2].t0;
    CHECK(reports(b, "empty parameter range", NULL), "empty edge not reported");
    b->edges[2].t1 = 1.0;
    b->coedges[5].edge = 99;
    CHECK(reports(b, "out of range", NULL), "bad index not reported");
    b->coedges[5].edge = 2;
    reports(b, NULL, &n);
    CHECK(n == 0, "repaired tetrahedron: %d problems", n);
    cb_topo_body_free(b);

    /* Three faces: open, which a closed shell must not be. */
    b = tetrahedron(3);
    CHECK(reports(b, "used by 1 coedge in closed shell", NULL), "open closed shell not reported");
    b->shells[0].closed = 0;
    reports(b, NULL, &n);
    CHECK(n == 0, "open shell declared open: %d problems", n);
    cb_topo_body_free(b);
}


/* ---------------------------------------------------------------- degenerate faces --------- */

/* A closed polyhedron with planar faces and line edges: the vertices P, faces as vertex cycles
 * (counterclockwise seen from outside) of deg[f] vertices each, one after the other in cyc.
 * Each face lies on the plane through its first vertex with Newell's normal, or, for a face
 * whose cycle spans no area, the plane z = that vertex's z. Pcurves computed; tolerance tol. */
static cb_topo_body *polyhedron(const double (*P)[3], int np, const int *cyc, const int *deg,
                                int nf, double tol)
{
    cb_topo_body *b = cb_topo_body_new();
    cb_error err;
    for (int k = 0; k < np; k++) {
        int v = cb_topo_body_add_vertex(b);
        memcpy(b->vertices[v].p, P[k], sizeof P[k]);
    }
    int edge[8][8];
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++)
            edge[i][j] = -1;
    int sh = cb_topo_body_add_shell(b), so = cb_topo_body_add_solid(b);
    b->solids[so] = (cb_topo_solid){.first = sh, .count = 1};
    b->shells[sh] = (cb_topo_shell){.first = 0, .count = nf, .closed = 1, .solid = so};
    for (int f = 0, at = 0; f < nf; at += deg[f++]) {
        const int *c = cyc + at;
        double n[3] = {0, 0, 0}, x[3];
        for (int k = 0; k < deg[f]; k++) {
            const double *p = P[c[k]], *q = P[c[(k + 1) % deg[f]]];
            n[0] += (p[1] - q[1]) * (p[2] + q[2]);
            n[1] += (p[2] - q[2]) * (p[0] + q[0]);
            n[2] += (p[0] - q[0]) * (p[1] + q[1]);
        }
        if (cb_vec3_norm(n) < 1e-14)
            n[0] = n[1] = 0, n[2] = 1;
        for (int i = 0; i < 3; i++)
            x[i] = P[c[1]][i] - P[c[0]][i];
        int fi = cb_topo_body_add_face(b), s = cb_topo_body_add_surface(b),
            l = cb_topo_body_add_loop(b);
        cb_frame fr;
        cb_frame_make(&fr, P[c[0]], n, x, &err);
        b->surfaces[s].kind = CB_SURFACE_ANALYTIC;
        cb_analytic_plane(&b->surfaces[s].analytic, &fr, &err);
        b->faces[fi] =
            (cb_topo_face){.surface = s, .same_sense = 1, .first = l, .count = 1, .shell = sh};
        b->loops[l] =
            (cb_topo_loop){.first = b->n_coedges, .count = deg[f], .outer = 1, .face = fi};
        for (int k = 0; k < deg[f]; k++) {
            int from = c[k], to = c[(k + 1) % deg[f]], lo = from < to ? from : to,
                hi = from < to ? to : from;
            if (edge[lo][hi] < 0) {
                int e = cb_topo_body_add_edge(b), cv = cb_topo_body_add_curve(b);
                double d[3] = {P[hi][0] - P[lo][0], P[hi][1] - P[lo][1], P[hi][2] - P[lo][2]};
                b->curves[cv].kind = CB_CURVE_LINE;
                b->curves[cv].r1 = cb_vec3_norm(d);
                cb_frame_make(&b->curves[cv].frame, P[lo], d, NULL, &err);
                b->edges[e] = (cb_topo_edge){
                    .curve = cv, .t0 = 0, .t1 = 1, .same_sense = 1, .v = {lo, hi}, .tol = tol};
                edge[lo][hi] = e;
            }
            int co = cb_topo_body_add_coedge(b);
            b->coedges[co] =
                (cb_topo_coedge){.edge = edge[lo][hi], .sense = from < to, .pcurve = -1, .loop = l};
        }
    }
    b->tol = tol;
    CHECK(cb_topo_body_index(b, &err) == CB_OK && cb_topo_compute_pcurves(b, tol, &err) == CB_OK,
          "polyhedron: %s", err.msg);
    return b;
}

/* The tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) with its edge from (1,0,0) to (0,1,0)
 * split at vertex 4, moved off the edge's midpoint by d (in the plane z = 0, away from the
 * solid): the bottom face becomes a quadrilateral and face 4 the sliver triangle between the
 * edge and its two halves, of area d / sqrt(2), no area at all for d = 0 (as the sliver of
 * tests/test_hostile.c, which tessellation cannot mesh). */
static cb_topo_body *split_tetrahedron(double d, double tol)
{
    double m = 0.5 + d / sqrt(2.0);
    const double P[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {m, m, 0}};
    static const int cyc[] = {0, 2, 4, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 2, 1, 4};
    static const int deg[] = {4, 3, 3, 3, 3};
    return polyhedron(P, 5, cyc, deg, 5, tol);
}

/* Sphere of radius 1 cut by the parallel at latitude v0 into two caps, each bounded by that
 * circle alone (one closed edge, no seam, no pole vertex): face 0 the north cap, face 1 the
 * south one. Their loops wrap around the sphere in u and end at a pole, where the area
 * integration must close them. */
static cb_topo_body *sphere_caps(double v0, double tol)
{
    cb_topo_body *b = cb_topo_body_new();
    cb_error err;
    int v = cb_topo_body_add_vertex(b);
    b->vertices[v] = (cb_topo_vertex){{cos(v0), 0, sin(v0)}};
    int cv = cb_topo_body_add_curve(b), e = cb_topo_body_add_edge(b);
    const double o[3] = {0, 0, sin(v0)}, z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    b->curves[cv].kind = CB_CURVE_CIRCLE;
    b->curves[cv].r1 = b->curves[cv].r2 = cos(v0);
    cb_frame_make(&b->curves[cv].frame, o, z, x, &err);
    b->edges[e] = (cb_topo_edge){
        .curve = cv, .t0 = 0, .t1 = 2 * PI, .same_sense = 1, .v = {v, v}, .tol = tol};
    int s = cb_topo_body_add_surface(b), sh = cb_topo_body_add_shell(b),
        so = cb_topo_body_add_solid(b);
    cb_frame world;
    const double origin[3] = {0, 0, 0};
    cb_frame_make(&world, origin, z, x, &err);
    b->surfaces[s].kind = CB_SURFACE_ANALYTIC;
    cb_analytic_sphere(&b->surfaces[s].analytic, &world, 1.0, &err);
    b->solids[so] = (cb_topo_solid){.first = sh, .count = 1};
    b->shells[sh] = (cb_topo_shell){.first = 0, .count = 2, .closed = 1, .solid = so};
    for (int k = 0; k < 2; k++) {
        int f = cb_topo_body_add_face(b), l = cb_topo_body_add_loop(b),
            c = cb_topo_body_add_coedge(b);
        b->faces[f] = (cb_topo_face){.surface = s, .same_sense = 1, .first = l, .count = 1,
                                     .shell = sh};
        b->loops[l] = (cb_topo_loop){.first = c, .count = 1, .outer = 1, .face = f};
        /* Outward normals: the north cap runs east (+u) round its bound, the south one west.
         * Both over the pcurve (u, v) = (t, v0), the circle's own parameter being u. */
        int pc = cb_topo_body_add_pcurve(b);
        const double po[3] = {0, v0, 0}, pd[3] = {1, 0, 0};
        b->pcurves[pc].kind = CB_CURVE_LINE;
        b->pcurves[pc].r1 = 1;
        cb_frame_make(&b->pcurves[pc].frame, po, pd, NULL, &err);
        b->coedges[c] = (cb_topo_coedge){.edge = e, .sense = k == 0, .pcurve = pc, .loop = l};
    }
    b->tol = tol;
    CHECK(cb_topo_body_index(b, &err) == CB_OK, "sphere caps: %s", err.msg);
    return b;
}

/* Validates b at tolerance tol: 1 when some problem contains `what`, *n the count. */
static int reports_at(cb_topo_body *b, double tol, const char *what, int *n)
{
    cb_topo_report r;
    cb_topo_report_init(&r);
    cb_error err;
    CHECK(cb_topo_validate(&r, b, tol, 7, &err) == CB_OK, "validate: %s", err.msg);
    int found = 0;
    for (int k = 0; k < r.n; k++)
        found |= what && strstr(r.items[k], what) != NULL;
    *n = r.n;
    cb_topo_report_clear(&r);
    return found;
}

static void test_degenerate_faces(void)
{
    int n;
    /* A face whose loop folds back on a line passed validation, and tessellation then failed
     * on it. Face 4 is the sliver; at d = 1e-12 it is still narrower than the tolerance 1e-9;
     * at d = 1e-6 it is a face. */
    cb_topo_body *b = split_tetrahedron(0, 1e-9);
    CHECK(reports_at(b, 0, "face 4: degenerate", &n) && n == 1,
          "zero-area face 4 not reported alone (%d problems)", n);
    cb_topo_body_free(b);
    b = split_tetrahedron(1e-12, 1e-9);
    CHECK(reports_at(b, 0, "face 4: degenerate", &n) && n == 1,
          "face 4 of width 1e-12 not reported alone (%d problems)", n);
    cb_topo_body_free(b);
    b = split_tetrahedron(1e-6, 1e-9);
    reports_at(b, 0, NULL, &n);
    CHECK(n == 0, "face 4 of width 1e-6 (area 7e-7): %d problems", n);
    cb_topo_body_free(b);

    /* Caps bounded by one circle: closed at the right pole, each measures its own area. The
     * limit is tol * loop length: at latitude 0.5 the north cap (area 2 pi (1 - sin 0.5) =
     * 3.27, loop 2 pi cos 0.5 = 5.51) is degenerate above tol = 0.593, the south cap (9.29)
     * above 1.69. */
    b = sphere_caps(0.5, 1e-9);
    reports_at(b, 0, NULL, &n);
    CHECK(n == 0, "sphere caps: %d problems", n);
    CHECK(!reports_at(b, 0.55, "degenerate", &n), "sphere caps at tol 0.55: degenerate");
    CHECK(reports_at(b, 0.65, "face 0: degenerate", &n) && n == 1,
          "sphere caps at tol 0.65: north cap not reported alone (%d problems)", n);
    cb_topo_body_free(b);

    /* A flat cone, radius 1 and height 0.2: its side through the apex (area pi s = 3.20 for
     * the slant s = 1.02; loop: the circle and the seam twice, 8.32) is degenerate above
     * tol = 0.385, its disc (pi, loop 2 pi) above 0.5. */
    cb_error err;
    CHECK(cb_prim_cone(&b, NULL, 1, 0, 0.2, 0, 1e-9, &err) == CB_OK, "cone: %s", err.msg);
    if (b) {
        CHECK(!reports_at(b, 0.35, "degenerate", &n), "cone at tol 0.35: degenerate");
        CHECK(reports_at(b, 0.42, "face 0: degenerate", &n) && n == 1,
              "cone at tol 0.42: side (face 0) not reported alone (%d problems)", n);
        cb_topo_body_free(b);
    }

    /* Every primitive, analytic or B-spline, small or large: its faces have area (spheres
     * bounded by their seam and poles, cones by an apex, tori by two seams). (At 1e-6 the
     * B-spline cylinder and cone are not built: their pcurve fit at tolerance 1e-15 stalls.) */
    for (int nurbs = 0; nurbs < 2; nurbs++)
        for (int scale = -3; scale <= 6; scale += 3) {
            double s = pow(10.0, scale);
            cb_topo_body *p[6] = {NULL};
            const double lo[3] = {0, 0, 0}, hi[3] = {s, 2 * s, 3 * s};
            cb_prim_box(&p[0], NULL, lo, hi, nurbs, 0, &err);
            cb_prim_sphere(&p[1], NULL, s, nurbs, 0, &err);
            cb_prim_ellipsoid(&p[2], NULL, s, 2 * s, 0.5 * s, nurbs, 0, &err);
            cb_prim_cylinder(&p[3], NULL, s, 3 * s, nurbs, 0, &err);
            cb_prim_cone(&p[4], NULL, 0, s, 2 * s, nurbs, 0, &err);
            cb_prim_torus(&p[5], NULL, 3 * s, s, nurbs, 0, &err);
            for (int k = 0; k < 6; k++) {
                CHECK(p[k] != NULL, "primitive %d (nurbs %d, scale %g) not built", k, nurbs, s);
                if (!p[k])
                    continue;
                reports_at(p[k], 0, NULL, &n);
                CHECK(n == 0, "primitive %d (nurbs %d, scale %g): %d problems", k, nurbs, s, n);
                cb_topo_body_free(p[k]);
            }
        }
}

/* Points of a curve through a sphere's poles (a meridian, as a plane through the axis cuts
 * it), with the longitude an inversion leaves free there set arbitrarily: each run of pole
 * points takes the longitude of the point before it, a run at the start that of the point
 * after it; the latitude is never touched. */
static void test_settle_poles(void)
{
    cb_topo_body *b = NULL;
    cb_error err;
    CHECK(cb_prim_sphere(&b, NULL, 1.5, 0, 0, &err) == CB_OK, "sphere: %s", err.msg);
    if (!b)
        return;
    cb_topo_inverter inv;
    CHECK(cb_topo_inverter_init(&inv, b->surfaces + b->faces[0].surface, 1e-9, &err) == CB_OK,
          "inverter: %s", err.msg);
    const double h = 0.5 * 3.14159265358979323846;
    /* south pole x 3, meridian u = 1, north pole x 2, meridian u = 4, south pole x 2 */
    double uv[][2] = {{0.3, -h}, {2.0, -h}, {5.0, -h}, {1, -1}, {1, 0}, {1, 1},  {6.0, h},
                      {0.1, h},  {4, 1},    {4, 0},    {4, -1}, {2.5, -h}, {0.7, -h}};
    const double want[] = {1, 1, 1, 1, 1, 1, 1, 1, 4, 4, 4, 4, 4};
    int n = (int)(sizeof uv / sizeof uv[0]);
    double v0[13];
    for (int i = 0; i < n; i++)
        v0[i] = uv[i][1];
    cb_topo_settle_poles(uv[0], sizeof uv[0], n, &inv);
    for (int i = 0; i < n; i++)
        CHECK(uv[i][0] == want[i] && uv[i][1] == v0[i], "point %d: (%g, %g), want (%g, %g)", i,
              uv[i][0], uv[i][1], want[i], v0[i]);
    cb_topo_inverter_clear(&inv);
    cb_topo_body_free(b);
}

/* Worst |S_nurbs(st) - s(uv)| over a grid of the B-spline's domain, uv the mapped parameters,
 * checking on the way that the map is strictly increasing in each direction and takes the
 * domain's corners to want = {u0, u1, v0, v1}. */
static double check_nurbs_form(const cb_topo_surface *s, const double range[4],
                               const double want[4], int exact, const char *what)
{
    cb_nurbs_surface_t n;
    cb_nurbs_surface_init(n);
    cb_error err;
    cb_status st = cb_topo_surface_to_nurbs(n, s, range, exact, &err);
    CHECK(st == CB_OK, "%s: to_nurbs: %s", what, err.msg);
    if (st)
        return HUGE_VAL;
    double dom[4], worst = 0;
    cb_nurbs_surface_domain(n, dom);
    enum { G = 23 };
    double prev_u[G + 1], prev_v = -HUGE_VAL;
    for (int i = 0; i <= G; i++) {
        double su = i == G ? dom[1] : dom[0] + (dom[1] - dom[0]) * i / G;
        for (int j = 0; j <= G; j++) {
            double sv = j == G ? dom[3] : dom[2] + (dom[3] - dom[2]) * j / G, p[3], d[6][3], uv[2];
            cb_nurbs_surface_eval(p, n, su, sv);
            cb_topo_surface_nurbs_param(uv, s, range, exact, (double[2]){su, sv});
            cb_topo_surface_eval_derivs(d, s, uv[0], uv[1]);
            worst = fmax(worst, cb_vec3_dist(p, d[0]));
            if (i > 0)
                CHECK(uv[0] > prev_u[j], "%s: u map not increasing at s = %g", what, su);
            if (j > 0)
                CHECK(uv[1] > prev_v, "%s: v map not increasing at t = %g", what, sv);
            prev_u[j] = uv[0];
            prev_v = uv[1];
            if ((i == 0 || i == G) && (j == 0 || j == G))
                CHECK(uv[0] == want[i ? 1 : 0] && uv[1] == want[j ? 3 : 2],
                      "%s: corner (%g, %g) maps to (%.17g, %.17g), want (%.17g, %.17g)", what, su,
                      sv, uv[0], uv[1], want[i ? 1 : 0], want[j ? 3 : 2]);
        }
    }
    cb_nurbs_surface_clear(n);
    CHECK(worst <= 1e-12 * 10, "%s: B-spline form off the surface by %g", what, worst);
    return worst;
}

/* cb_topo_surface_to_nurbs and cb_topo_surface_nurbs_param: the B-spline form of revolutions
 * and extrusions with line, circle, ellipse and B-spline profiles (planar or not, rational or
 * not, the profile cut to a sub-range or whole), full turns (exact quarter weights) and
 * partial ranges, and of analytic surfaces, lies on the surface at the mapped parameters, and
 * the map is an increasing bijection onto the range. */
static void test_nurbs_forms(void)
{
    check_rng rng = {23};
    cb_error err;
    double worst = 0;
    for (int trial = 0; trial < 24; trial++) {
        cb_frame f, g;
        random_frame(&f, &rng);
        random_frame(&g, &rng);
        int full = trial % 3 == 0;
        double a0 = check_rng_uniform(&rng, -4, 4), a1 = a0 + check_rng_uniform(&rng, 0.3, 6.2);
        double u_range[2] = {full ? 0 : a0, full ? 2 * PI : a1};
        for (int pk = 0; pk < 5; pk++) {
            cb_topo_surface s;
            cb_topo_surface_init(&s);
            cb_topo_curve *c = &s.profile;
            c->frame = g;
            c->r1 = check_rng_uniform(&rng, 0.5, 2);
            c->r2 = check_rng_uniform(&rng, 0.5, 2);
            double p_range[2] = {check_rng_uniform(&rng, -3, 0), 0}, want_p[2];
            p_range[1] = p_range[0] + check_rng_uniform(&rng, 0.5, 6.2);
            if (pk == 0) {
                c->kind = CB_CURVE_LINE; /* skew to the axis: no plane through it */
            } else if (pk == 1 || pk == 2) {
                c->kind = pk == 1 ? CB_CURVE_CIRCLE : CB_CURVE_ELLIPSE;
            } else {
                c->kind = CB_CURVE_NURBS;
                if (pk == 3) {
                    CHECK(cb_nurbs_curve_arc(c->nurbs, g.o, g.x, g.z, c->r1, -1.0, 2.5, &err) ==
                              CB_OK,
                          "%s", err.msg);
                } else {
                    double knots[8] = {0, 0, 0, 0, 1, 1, 1, 1}, pts[12];
                    for (int k = 0; k < 12; k++)
                        pts[k] = check_rng_uniform(&rng, -3, 3);
                    CHECK(cb_nurbs_curve_make(c->nurbs, 3, knots, 8, pts, NULL, 4, &err) == CB_OK,
                          "%s", err.msg);
                }
                double lo, hi;
                cb_nurbs_curve_domain(c->nurbs, &lo, &hi);
                /* every other trial a sub-range (the B-spline is cut), else the whole */
                p_range[0] = trial % 2 ? lo + 0.3 * (hi - lo) : lo - 1;
                p_range[1] = trial % 2 ? lo + 0.8 * (hi - lo) : hi + 1;
            }
            want_p[0] = p_range[0];
            want_p[1] = p_range[1];
            if (c->kind == CB_CURVE_NURBS && trial % 2 == 0)
                cb_nurbs_curve_domain(c->nurbs, &want_p[0], &want_p[1]);
            char what[96];
            /* revolution about f's axis */
            s.kind = CB_SURFACE_REVOLUTION;
            s.frame = f;
            double range[4] = {u_range[0], u_range[1], p_range[0], p_range[1]};
            double want[4] = {u_range[0], u_range[1], want_p[0], want_p[1]};
            snprintf(what, sizeof what, "trial %d revolution of a %s%s", trial,
                     cb_curve_kind_name(c->kind), full ? " (full turn)" : "");
            worst = fmax(worst, check_nurbs_form(&s, range, want, trial % 2, what));
            /* extrusion along a skew direction */
            s.kind = CB_SURFACE_EXTRUSION;
            for (int k = 0; k < 3; k++)
                s.dir[k] = 1.7 * f.z[k] + 0.3 * f.x[k];
            double erange[4] = {p_range[0], p_range[1], -1.5, 2.0};
            double ewant[4] = {want_p[0], want_p[1], -1.5, 2.0};
            snprintf(what, sizeof what, "trial %d extrusion of a %s", trial,
                     cb_curve_kind_name(c->kind));
            worst = fmax(worst, check_nurbs_form(&s, erange, ewant, trial % 4 < 2, what));
            cb_topo_surface_clear(&s);
        }
        /* analytic surfaces through the same service */
        cb_topo_surface s;
        cb_topo_surface_init(&s);
        s.kind = CB_SURFACE_ANALYTIC;
        cb_analytic_torus(&s.analytic, &f, 3.0, 1.0, &err);
        double tr[4] = {u_range[0], u_range[1], -2.0, 1.5};
        worst = fmax(worst, check_nurbs_form(&s, tr, tr, trial % 2, "torus"));
        cb_analytic_cone(&s.analytic, &f, 1.0, 0.4, &err);
        double cr[4] = {u_range[0], u_range[1], 0.5, 3.0};
        worst = fmax(worst, check_nurbs_form(&s, cr, cr, trial % 2, "cone"));
        cb_topo_surface_clear(&s);
    }
    /* the arc map alone: the identity at the knots, strictly between them, exact or not */
    for (int exact = 0; exact < 2; exact++) {
        double k0 = 0, k1 = 2 * PI;
        for (int q = 0; q <= 4; q++) {
            double t = k0 + q * 0.5 * PI;
            CHECK(cb_nurbs_arc_angle(k0, k1, exact, t) == t, "arc angle at knot %g", t);
        }
        double t = 0.3, a = cb_nurbs_arc_angle(k0, k1, exact, t);
        CHECK(a > 0 && a < 0.5 * PI, "arc angle at 0.3: %g", a);
        CHECK(cb_nurbs_arc_angle(k0, k1, exact, -1) == k0 && cb_nurbs_arc_angle(k0, k1, exact, 9) == k1,
              "arc angle outside the domain not clamped");
    }
    printf("B-spline forms of revolutions, extrusions, analytic surfaces: worst %.3g\n", worst);
}

int main(void)
{
    test_settle_poles();
    test_surfaces();
    test_curves();
    test_body();
    test_degenerate_faces();
    test_nurbs_forms();
    return check_report("brep_topo");
}
