/* Triangle meshes: the value type (volume, area, merging), the reference shapes, the CGAL checks
 * on good and broken meshes, and the exit codes of `colibri check`. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "brep/mesh.h"
#include "brep/mesh_check.h"
#include "brep/mesh_shapes.h"
#include "check.h"
#include "check_cli.h"
#include "io/mesh.h"

/* CGAL's exact predicates are slow under AddressSanitizer: smaller meshes there. */
#if defined(__SANITIZE_ADDRESS__)
enum { ICO_LEVELS = 3, TORUS_NU = 16, TORUS_NV = 8 };
#else
enum { ICO_LEVELS = 6, TORUS_NU = 64, TORUS_NV = 32 };
#endif

static const double PI = 3.141592653589793;

static double rel_diff(double a, double b)
{
    return fabs(a - b) / fmax(fabs(a), fabs(b));
}

static void print_report(const char *name, const cb_mesh_check_report *r)
{
    fprintf(stderr,
            "  %s: v %d t %d closed %d edge %d vertex %d oriented %d tri %d self %d bounds %d "
            "outward %d volume %.17g (boundary %d, nm edges %d, nm vertices %d, misoriented %d)\n",
            name, r->vertices, r->triangles, r->closed, r->edge_manifold, r->vertex_manifold,
            r->oriented, r->triangle_mesh, r->self_intersections, r->bounds_volume, r->outward,
            r->volume, r->boundary_edges, r->nonmanifold_edges, r->nonmanifold_vertices,
            r->misoriented_edges);
}

/* A good mesh passes every check, and CGAL's volume agrees with ours to 1e-12. */
static void expect_good(const char *name, const cb_mesh_t m, double volume, double vol_tol)
{
    cb_mesh_check_report r;
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_mesh_check(&r, m, &err);
    CHECK(st == CB_OK, "%s: check failed: %s", name, err.msg);
    int ok = cb_mesh_check_passed(&r);
    CHECK(ok, "%s: a good mesh fails its checks", name);
    if (!ok)
        print_report(name, &r);
    CHECK(r.vertices == m->n_vertices && r.triangles == m->n_triangles, "%s: counts %d %d", name,
          r.vertices, r.triangles);
    double mine = cb_mesh_volume(m);
    CHECK(rel_diff(r.volume, mine) < 1e-12, "%s: CGAL volume %.17g, ours %.17g", name, r.volume,
          mine);
    CHECK(rel_diff(mine, volume) < vol_tol, "%s: volume %.17g, expected %.17g (tolerance %g)",
          name, mine, volume, vol_tol);
}

static void test_good_shapes(void)
{
    cb_mesh_t m;
    cb_mesh_init(m);
    cb_error err;
    const double origin[3] = {0, 0, 0}, far[3] = {1e4, -2e4, 3e4};

    const double tet[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    CHECK(cb_mesh_tetrahedron(m, tet, &err) == CB_OK, "tetrahedron: %s", err.msg);
    expect_good("tetrahedron", m, 1.0 / 6, 1e-15);
    const double tet_neg[4][3] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
    CHECK(cb_mesh_tetrahedron(m, tet_neg, &err) == CB_OK, "tetrahedron: %s", err.msg);
    expect_good("tetrahedron (left-handed input)", m, 1.0 / 6, 1e-15);

    const double lo[3] = {-1, 2, 0.5}, hi[3] = {3, 2.5, 4};
    CHECK(cb_mesh_box(m, lo, hi, &err) == CB_OK, "box: %s", err.msg);
    expect_good("box", m, 4 * 0.5 * 3.5, 1e-15);
    double area = cb_mesh_area(m);
    CHECK(rel_diff(area, 2 * (4 * 0.5 + 0.5 * 3.5 + 3.5 * 4)) < 1e-15, "box area %.17g", area);

    /* The icosphere's volume converges to the ball's from below, four times closer per level. */
    double ball = 4.0 / 3 * PI * 8, prev_err = 0;
    for (int level = 0; level <= ICO_LEVELS; level++) {
        char name[64];
        snprintf(name, sizeof name, "icosphere level %d", level);
        CHECK(cb_mesh_icosphere(m, far, 2, level, &err) == CB_OK, "%s: %s", name, err.msg);
        CHECK(m->n_vertices == 10 * (1 << 2 * level) + 2 && m->n_triangles == 20 << 2 * level,
              "%s: %d vertices, %d triangles", name, m->n_vertices, m->n_triangles);
        double v = cb_mesh_volume(m), e = (ball - v) / ball;
        expect_good(name, m, ball, 0.7);
        CHECK(e > 0, "%s: volume %.17g not below the ball's %.17g", name, v, ball);
        /* The first levels are too coarse for the asymptotic ratio. */
        double ratio = level > 0 ? prev_err / e : 0;
        CHECK(level < 3 || (ratio > 3.8 && ratio < 4.2), "%s: error ratio %.3f, expected about 4",
              name, ratio);
        printf("icosphere level %d: %d triangles, relative volume error %.3e (ratio %.3f)\n",
               level, m->n_triangles, e, ratio);
        prev_err = e;
    }

    /* Torus: the exact volume of the sampled polyhedron is not the torus's; its error is
     * second order in the sampling, so halving both steps must cut it about four times. */
    double torus = 2 * PI * PI * 3 * 1 * 1, errs[2];
    for (int k = 0; k < 2; k++) {
        int nu = TORUS_NU << k, nv = TORUS_NV << k;
        CHECK(cb_mesh_torus(m, origin, 3, 1, nu, nv, &err) == CB_OK, "torus: %s", err.msg);
        expect_good("torus", m, torus, 0.2);
        errs[k] = rel_diff(cb_mesh_volume(m), torus);
    }
    CHECK(errs[0] / errs[1] > 3.5 && errs[0] / errs[1] < 4.5, "torus error %.3e then %.3e",
          errs[0], errs[1]);
    printf("torus %dx%d: relative volume error %.3e; %dx%d: %.3e\n", TORUS_NU, TORUS_NV, errs[0],
           2 * TORUS_NU, 2 * TORUS_NV, errs[1]);
    cb_mesh_clear(m);
}

static void test_bad_shapes(void)
{
    cb_mesh_t m, b;
    cb_mesh_init(m);
    cb_mesh_init(b);
    cb_error err;
    cb_mesh_check_report r;
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};

    /* One triangle removed: three boundary edges; nothing after self-intersection is run. */
    cb_mesh_box(m, lo, hi, &err);
    m->n_triangles--;
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK, "open box: %s", err.msg);
    CHECK(!r.closed && r.boundary_edges == 3 && r.edge_manifold && r.vertex_manifold &&
              r.oriented && r.self_intersections == 0 && r.bounds_volume == -1 &&
              r.outward == -1 && isnan(r.volume) && !cb_mesh_check_passed(&r),
          "open box misreported");

    /* Every triangle flipped: closed and manifold, but inward with volume -1. CGAL still says
     * it bounds a volume (the one outside it). */
    cb_mesh_box(m, lo, hi, &err);
    for (int f = 0; f < m->n_triangles; f++) {
        int t = m->tri[3 * f + 1];
        m->tri[3 * f + 1] = m->tri[3 * f + 2];
        m->tri[3 * f + 2] = t;
    }
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK, "flipped box: %s", err.msg);
    CHECK(r.closed && r.oriented && r.self_intersections == 0 && r.outward == 0 &&
              r.bounds_volume == 1 && rel_diff(r.volume, -1) < 1e-15 &&
              !cb_mesh_check_passed(&r),
          "flipped box misreported");
    CHECK(cb_mesh_volume(m) == -1, "flipped box: our volume %.17g", cb_mesh_volume(m));

    /* One triangle flipped: closed but inconsistently oriented on its three edges. */
    cb_mesh_box(m, lo, hi, &err);
    int t0 = m->tri[1];
    m->tri[1] = m->tri[2];
    m->tri[2] = t0;
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK, "box with a flipped triangle: %s", err.msg);
    CHECK(r.closed && !r.oriented && r.misoriented_edges == 3 && r.self_intersections == -1 &&
              !cb_mesh_check_passed(&r),
          "box with one flipped triangle misreported");

    /* Two interpenetrating boxes in one mesh: each is fine, together they cross. */
    const double lo2[3] = {0.5, 0.5, 0.5}, hi2[3] = {1.5, 1.5, 1.5};
    cb_mesh_box(m, lo, hi, &err);
    cb_mesh_box(b, lo2, hi2, &err);
    CHECK(cb_mesh_append(m, b, &err) == CB_OK, "append: %s", err.msg);
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK, "crossing boxes: %s", err.msg);
    CHECK(r.closed && r.edge_manifold && r.vertex_manifold && r.oriented &&
              r.self_intersections == 1 && r.bounds_volume == -1 && !cb_mesh_check_passed(&r),
          "crossing boxes misreported");

    /* Disjoint boxes, and a box inside another facing inward (a solid with a void), bound a
     * volume; the same inner box facing outward does not. */
    const double lo3[3] = {2, 0, 0}, hi3[3] = {3, 1, 1};
    cb_mesh_box(m, lo, hi, &err);
    cb_mesh_box(b, lo3, hi3, &err);
    cb_mesh_append(m, b, &err);
    expect_good("two disjoint boxes", m, 2, 1e-15);
    const double lo4[3] = {0.25, 0.25, 0.25}, hi4[3] = {0.75, 0.75, 0.75};
    cb_mesh_box(m, lo, hi, &err);
    cb_mesh_box(b, lo4, hi4, &err);
    cb_mesh_append(m, b, &err);
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK && r.self_intersections == 0 &&
              r.bounds_volume == 0 && !cb_mesh_check_passed(&r),
          "box in a box, both outward, misreported");
    for (int f = 12; f < m->n_triangles; f++) {
        int t = m->tri[3 * f + 1];
        m->tri[3 * f + 1] = m->tri[3 * f + 2];
        m->tri[3 * f + 2] = t;
    }
    expect_good("box with a void", m, 1 - 0.125, 1e-15);

    /* A fin on a box edge: three triangles on that edge. */
    cb_mesh_box(m, lo, hi, &err);
    const double fin[3] = {-1, -1, 0.5};
    cb_mesh_append_vertex(m, fin, &err);
    cb_mesh_append_triangle(m, 0, 4, 8, &err);
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK, "fin: %s", err.msg);
    CHECK(!r.closed && !r.edge_manifold && r.nonmanifold_edges == 1 && r.boundary_edges == 2 &&
              r.self_intersections == -1 && !cb_mesh_check_passed(&r),
          "box with a fin misreported");

    /* Two boxes sharing one corner vertex: closed, edge-manifold, but that vertex has two fans. */
    const double lo5[3] = {1, 1, 1}, hi5[3] = {2, 2, 2};
    cb_mesh_box(m, lo, hi, &err);
    cb_mesh_box(b, lo5, hi5, &err);
    cb_mesh_append(m, b, &err);
    int collapsed = -1;
    CHECK(cb_mesh_merge_vertices(m, 0, &collapsed, &err) == CB_OK && m->n_vertices == 15 &&
              collapsed == 0,
          "corner merge: %d vertices, %d collapsed", m->n_vertices, collapsed);
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK, "pinched boxes: %s", err.msg);
    CHECK(r.closed && r.edge_manifold && !r.vertex_manifold && r.nonmanifold_vertices == 1 &&
              !cb_mesh_check_passed(&r),
          "boxes sharing a corner misreported");

    /* A tetrahedron with its apex moved onto a base edge: one face is degenerate (collinear
     * corners), the others lie flat on the base; CGAL counts both as self-intersections. */
    const double tet[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    cb_mesh_tetrahedron(m, tet, &err);
    m->xyz[9] = 0.5;
    m->xyz[10] = m->xyz[11] = 0;
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK && r.closed && r.self_intersections == 1 &&
              !cb_mesh_check_passed(&r),
          "flat tetrahedron: self-intersections %d", r.self_intersections);

    /* The empty mesh bounds nothing. */
    cb_mesh_clear(m);
    CHECK(cb_mesh_check(&r, m, &err) == CB_OK, "empty: %s", err.msg);
    CHECK(!r.closed && r.triangles == 0 && r.vertices == 0 && !cb_mesh_check_passed(&r),
          "empty mesh misreported");
    cb_mesh_clear(m);
    cb_mesh_clear(b);
}

/* Two closed meshes a and b put together, their contacts counted at eps. */
static cb_status contacts_of(cb_mesh_contacts *c, const cb_mesh_t a, const cb_mesh_t b, double eps,
                             cb_error *err)
{
    cb_mesh_t m;
    cb_mesh_init(m);
    cb_status st = cb_mesh_append(m, a, err);
    if (!st)
        st = cb_mesh_append(m, b, err);
    if (!st)
        st = cb_mesh_check_contacts(c, m, eps, err);
    cb_mesh_clear(m);
    return st;
}

/* Where a mesh meets itself, touching is told from crossing: boxes that share a corner, an
 * edge or part of an edge, a wedge standing on a face, against boxes and wedges that cut into
 * each other. Exact coordinates: the counts do not depend on eps. */
static void test_contacts(void)
{
    cb_mesh_t a, b, m;
    cb_mesh_init(a);
    cb_mesh_init(b);
    cb_mesh_init(m);
    cb_error err;
    cb_mesh_contacts c;
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    cb_mesh_box(a, lo, hi, &err);
    static const struct {
        const char *name;
        double lo[3], hi[3];
        int crossing; /* expected: 0, or more than 0 */
    } boxes[] = {{"a shared corner", {1, 1, 1}, {2, 2, 2}, 0},
                 {"a shared edge", {1, 1, 0}, {2, 2, 1}, 0},
                 {"part of an edge", {1, 1, 0.25}, {2, 2, 2}, 0},
                 {"a corner cut in", {0.75, 0.75, 0.75}, {2, 2, 2}, 1},
                 {"an edge cut in", {0.9, 0.9, 0}, {2, 2, 1}, 1}};
    for (size_t k = 0; k < sizeof boxes / sizeof boxes[0]; k++) {
        cb_mesh_box(b, boxes[k].lo, boxes[k].hi, &err);
        for (int e = 0; e < 3; e++) {
            double eps = e == 0 ? 1e-12 : e == 1 ? 1e-6 : 1e-3;
            cb_status st = contacts_of(&c, a, b, eps, &err);
            CHECK(st == CB_OK && c.touching + c.crossing > 0 &&
                      (boxes[k].crossing ? c.crossing > 0 : c.crossing == 0),
                  "boxes meeting at %s (eps %g): %d pairs touching, %d crossing (%s)",
                  boxes[k].name, eps, c.touching, c.crossing, st ? err.msg : "");
        }
    }

    /* The corner shared as one vertex of two fans: the same contact. */
    cb_mesh_box(b, boxes[0].lo, boxes[0].hi, &err);
    cb_mesh_append(m, a, &err);
    cb_mesh_append(m, b, &err);
    cb_mesh_merge_vertices(m, 0, NULL, &err);
    CHECK(m->n_vertices == 15 && cb_mesh_check_contacts(&c, m, 1e-9, &err) == CB_OK &&
              c.touching > 0 && c.crossing == 0,
          "pinched boxes: %d vertices, %d pairs touching, %d crossing", m->n_vertices, c.touching,
          c.crossing);

    /* A wedge (tetrahedron) standing on its edge in the middle of the box's top face touches
     * it along that edge, inside the face's triangles; pushed down by 0.01 it cuts in. */
    double wedge[4][3] = {{0.3, 0.5, 1}, {0.7, 0.5, 1}, {0.5, 0.3, 1.5}, {0.5, 0.7, 1.5}};
    for (int sunk = 0; sunk < 2; sunk++) {
        cb_mesh_tetrahedron(b, (const double(*)[3])wedge, &err);
        cb_status st = contacts_of(&c, a, b, 1e-9, &err);
        CHECK(st == CB_OK && c.touching + c.crossing > 0 && (sunk ? c.crossing > 0 : c.crossing == 0),
              "wedge %s the face: %d pairs touching, %d crossing (%s)", sunk ? "cut into" : "on",
              c.touching, c.crossing, st ? err.msg : "");
        for (int k = 0; k < 4; k++)
            wedge[k][2] -= 0.01;
    }

    /* Bad input: an open mesh, a misoriented one, eps not a positive distance. */
    cb_mesh_box(m, lo, hi, &err);
    m->n_triangles--;
    CHECK(cb_mesh_check_contacts(&c, m, 1e-9, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "not closed") && c.touching == -1,
          "open box: %s", err.msg);
    cb_mesh_box(m, lo, hi, &err);
    int t0 = m->tri[1];
    m->tri[1] = m->tri[2];
    m->tri[2] = t0;
    CHECK(cb_mesh_check_contacts(&c, m, 1e-9, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "1 misoriented") == NULL && strstr(err.msg, "3 misoriented"),
          "box with a flipped triangle: %s", err.msg);
    cb_mesh_box(m, lo, hi, &err);
    CHECK(cb_mesh_check_contacts(&c, m, 0, &err) == CB_ERR_INVALID &&
              cb_mesh_check_contacts(&c, m, NAN, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "eps"),
          "eps 0 or NaN accepted: %s", err.msg);
    CHECK(cb_mesh_check_contacts(&c, m, 1e-9, &err) == CB_OK && c.touching == 0 &&
              c.crossing == 0,
          "one box: %d pairs touching, %d crossing", c.touching, c.crossing);
    cb_mesh_clear(a);
    cb_mesh_clear(b);
    cb_mesh_clear(m);
}

/* Identities of the value type on random input. */
static void test_value_type(void)
{
    check_rng rng = {42};
    cb_mesh_t m, s;
    cb_mesh_init(m);
    cb_mesh_init(s);
    cb_error err;
    for (int trial = 0; trial < 200; trial++) {
        double p[4][3], c[3];
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                p[i][k] = check_rng_uniform(&rng, -10, 10);
        for (int k = 0; k < 3; k++)
            c[k] = check_rng_uniform(&rng, -1e3, 1e3);
        if (cb_mesh_tetrahedron(m, p, &err))
            continue;
        double u[3], v[3], w[3];
        for (int k = 0; k < 3; k++) {
            u[k] = p[1][k] - p[0][k];
            v[k] = p[2][k] - p[0][k];
            w[k] = p[3][k] - p[0][k];
        }
        double det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                     u[2] * (v[0] * w[1] - v[1] * w[0]);
        double vol = cb_mesh_volume(m);
        CHECK(rel_diff(vol, fabs(det) / 6) < 1e-12, "trial %d: volume %.17g, |det|/6 %.17g",
              trial, vol, fabs(det) / 6);
        /* Translation moves no volume of a closed mesh. */
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                m->xyz[3 * i + k] += c[k];
        CHECK(rel_diff(cb_mesh_volume(m), vol) < 1e-9, "trial %d: translated volume %.17g",
              trial, cb_mesh_volume(m));
        /* A soup of separate triangles merges back to the four shared vertices. */
        cb_mesh_clear(s);
        for (int f = 0; f < 4; f++)
            for (int k = 0; k < 3; k++) {
                double q[3];
                for (int j = 0; j < 3; j++)
                    q[j] = m->xyz[3 * m->tri[3 * f + k] + j] + check_rng_uniform(&rng, -1e-9, 1e-9);
                cb_mesh_append_vertex(s, q, &err);
            }
        for (int f = 0; f < 4; f++)
            cb_mesh_append_triangle(s, 3 * f, 3 * f + 1, 3 * f + 2, &err);
        int collapsed = -1;
        CHECK(cb_mesh_merge_vertices(s, 1e-6, &collapsed, &err) == CB_OK && s->n_vertices == 4 &&
                  s->n_triangles == 4 && collapsed == 0,
              "trial %d: merged to %d vertices, %d triangles, %d collapsed", trial,
              s->n_vertices, s->n_triangles, collapsed);
        cb_mesh_check_report r;
        if (trial < 20) {
            CHECK(cb_mesh_check(&r, s, &err) == CB_OK && r.closed && r.oriented &&
                      r.vertex_manifold,
                  "trial %d: merged soup not closed and oriented", trial);
        }
    }
    /* Merging with a tolerance larger than a triangle collapses it. */
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1e-3};
    cb_mesh_box(m, lo, hi, &err);
    int collapsed = -1;
    CHECK(cb_mesh_merge_vertices(m, 0.01, &collapsed, &err) == CB_OK && m->n_vertices == 4 &&
              m->n_triangles == 4 && collapsed == 8,
          "thin box merged to %d vertices, %d triangles, %d collapsed", m->n_vertices,
          m->n_triangles, collapsed);
    CHECK(cb_mesh_merge_vertices(m, -1, NULL, &err) == CB_ERR_INVALID, "negative tolerance");
    CHECK(cb_mesh_merge_vertices(m, 1e-300, NULL, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "too small"),
          "tiny tolerance: %s", err.msg);
    /* Precondition failures name what is wrong. */
    CHECK(cb_mesh_append_triangle(m, 0, 1, 99, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "outside"),
          "cli_out of range: %s", err.msg);
    CHECK(cb_mesh_append_triangle(m, 0, 1, 1, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "repeats"),
          "repeated vertex: %s", err.msg);
    const double bad[3] = {0, NAN, 0};
    CHECK(cb_mesh_append_vertex(m, bad, &err) == CB_ERR_INVALID, "NaN vertex accepted");
    cb_mesh_clear(m);
    cb_mesh_clear(s);
}

/* ---------------------------------------------------------------- colibri check ------------ */

/* The number after "key": in a JSON text; NaN when absent. */
static double json_number(const char *json, const char *key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *p = strstr(json, pat);
    return p ? strtod(p + strlen(pat), NULL) : NAN;
}

static void test_cli(void)
{
    char dir[64], path[128], args[256];
    snprintf(dir, sizeof dir, "/tmp/colibri_check_%ld", (long)getpid());
    snprintf(args, sizeof args, "mkdir -p %s", dir);
    CHECK(system(args) == 0, "cannot make %s", dir);
    cb_mesh_t m;
    cb_mesh_init(m);
    cb_error err;
    const double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1};

    cli_expect("check --help", 0, "usage: colibri check MESH");
    cli_expect("check", 2, "usage: colibri check");
    cli_expect("check a.stl b.stl", 2, "usage: colibri check");
    cli_expect("check --bogus a.stl", 2, "usage: colibri check");

    cb_mesh_box(m, lo, hi, &err);
    snprintf(path, sizeof path, "%s/box.off", dir);
    CHECK(cb_mesh_write(path, m, NULL, &err) == CB_OK, "%s", err.msg);
    snprintf(args, sizeof args, "check %s", path);
    cli_expect(args, 0, "result: pass");
    cli_expect(args, 0, "volume: 2\n");
    snprintf(args, sizeof args, "check %s --json", path);
    cli_expect(args, 0,
           "\"vertices\": 8, \"triangles\": 12, \"closed\": true, \"manifold\": true, "
           "\"edge_manifold\": true, \"vertex_manifold\": true, \"oriented\": true, "
           "\"triangle_mesh\": true, \"self_intersections\": false, \"bounds_volume\": true, "
           "\"outward\": true, \"volume\": ");
    cli_expect(args, 0, "\"passed\": true}");
    CHECK(rel_diff(json_number(cli_out, "volume"), 2) < 1e-15, "JSON volume %.17g",
          json_number(cli_out, "volume"));

    for (int f = 0; f < m->n_triangles; f++) {
        int t = m->tri[3 * f];
        m->tri[3 * f] = m->tri[3 * f + 1];
        m->tri[3 * f + 1] = t;
    }
    snprintf(path, sizeof path, "%s/inward.stl", dir);
    CHECK(cb_mesh_write(path, m, NULL, &err) == CB_OK, "%s", err.msg);
    snprintf(args, sizeof args, "check %s", path);
    cli_expect(args, 1, "outward: no");
    snprintf(args, sizeof args, "check --json %s", path);
    cli_expect(args, 1, "\"outward\": false, \"volume\": ");
    CHECK(rel_diff(json_number(cli_out, "volume"), -2) < 1e-15, "JSON volume %.17g",
          json_number(cli_out, "volume"));

    m->n_triangles--;
    snprintf(path, sizeof path, "%s/open.ply", dir);
    CHECK(cb_mesh_write(path, m, NULL, &err) == CB_OK, "%s", err.msg);
    snprintf(args, sizeof args, "check %s", path);
    cli_expect(args, 1, "closed: no (3 boundary edges)");
    snprintf(args, sizeof args, "check --json %s", path);
    cli_expect(args, 1, "\"bounds_volume\": null, \"outward\": null, \"volume\": null");

    snprintf(args, sizeof args, "check %s/missing.obj", dir);
    cli_expect(args, 2, "missing.obj: cannot open");
    snprintf(path, sizeof path, "%s/garbage.off", dir);
    FILE *f = fopen(path, "w");
    fputs("this is not an OFF file\n\x01\x02\x03\n", f);
    fclose(f);
    snprintf(args, sizeof args, "check %s", path);
    cli_expect(args, 2, "garbage.off: ");
    snprintf(path, sizeof path, "%s/garbage.stl", dir);
    f = fopen(path, "w");
    fputs("solid nonsense\n  facet normal 0 0 1\n    outer loop\n      vertex 1 2\n", f);
    fclose(f);
    snprintf(args, sizeof args, "check %s", path);
    cli_expect(args, 2, "garbage.stl: ");
    snprintf(args, sizeof args, "check %s/box.step", dir);
    cli_expect(args, 2, "unknown mesh format");

    snprintf(args, sizeof args, "rm -rf %s", dir);
    CHECK(system(args) == 0, "cannot remove %s", dir);
    cb_mesh_clear(m);
}

int main(void)
{
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    test_value_type();
    test_good_shapes();
    test_bad_shapes();
    test_contacts();
    test_cli();
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("mesh_check: %.2f s\n",
           (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
    return check_report("mesh_check");
}
