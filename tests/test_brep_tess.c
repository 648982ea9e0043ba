/* Tessellation (brep/tess.h): every shipped model meshes closed, manifold, outward and free of
 * self-intersections (CGAL); the result does not depend on the thread count; the mesh volume
 * lies within area x chord tolerance of the reference volume and gets closer as the tolerance
 * shrinks; bad options and cancellation are reported. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "brep/mesh_check.h"
#include "brep/prim.h"
#include "brep/tess.h"
#include "check.h"
#include "io/step.h"
#include "models/models.h"

static const char *shared_dir(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    return d ? d : "../shared";
}

/* Reference figures of models/SOURCES.md (Open CASCADE, about 1e-7 relative), in mm^3 and
 * mm^2. */
typedef struct {
    const char *file;
    double volume, area;
} model_ref;

static const model_ref MODELS[] = {
    {"trj5_k1-al-214.stp", 7936.1475, 4952.8495},
    {"linkrods.step", 3.847013, 32.151437},
    {"ujoint_fork.step", 81046.104, 23955.819},
    {"ujoint_cross.step", 95097.336, 14307.078},
};

static cb_topo_body *load(const char *file)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/%s", shared_dir(), file);
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = cb_step_read(&b, path, &err);
    CHECK(st == CB_OK, "%s: %s", path, err.msg);
    return b;
}

static cb_topo_body *bird(void)
{
    cb_hummingbird_params p;
    cb_hummingbird_params_default(&p);
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = cb_model_hummingbird(&b, &p, &err);
    CHECK(st == CB_OK, "hummingbird: %s", err.msg);
    if (st)
        return NULL;
    st = cb_topo_compute_pcurves(b, b->tol, &err);
    CHECK(st == CB_OK, "hummingbird pcurves: %s", err.msg);
    return b;
}

static cb_status tess(cb_mesh_t m, const cb_topo_body *b, double chord, int threads,
                      cb_error *err)
{
    cb_tess_opts o;
    cb_tess_opts_init(&o);
    o.chord_tol = chord;
    cb_context ctx;
    cb_context_init(&ctx);
    ctx.threads = threads;
    return cb_tess_body(m, b, &o, &ctx, err);
}

static double default_chord(const cb_topo_body *b)
{
    cb_tess_opts o;
    cb_error err;
    cb_status st = cb_tess_opts_resolve(&o, NULL, b, &err);
    CHECK(st == CB_OK, "resolve: %s", err.msg);
    return o.chord_tol;
}

/* The checks every model must pass at chord tolerance `chord`; returns the mesh volume in model
 * units (NaN when the mesh could not be made). */
static double check_model(const char *name, const cb_topo_body *b, double chord)
{
    cb_mesh_t m1, m2;
    cb_mesh_init(m1);
    cb_mesh_init(m2);
    cb_error err;
    cb_status st = tess(m1, b, chord, 1, &err);
    CHECK(st == CB_OK, "%s: %s", name, err.msg);
    st = tess(m2, b, chord, 2, &err);
    CHECK(st == CB_OK, "%s (2 threads): %s", name, err.msg);
    CHECK(m1->n_vertices == m2->n_vertices && m1->n_triangles == m2->n_triangles,
          "%s: %d/%d vertices/triangles with 1 thread, %d/%d with 2", name, m1->n_vertices,
          m1->n_triangles, m2->n_vertices, m2->n_triangles);
    if (m1->n_vertices == m2->n_vertices && m1->n_triangles == m2->n_triangles) {
        CHECK(!memcmp(m1->xyz, m2->xyz, sizeof(double) * 3 * (size_t)m1->n_vertices),
              "%s: coordinates differ between 1 and 2 threads", name);
        CHECK(!memcmp(m1->tri, m2->tri, sizeof(int) * 3 * (size_t)m1->n_triangles),
              "%s: triangles differ between 1 and 2 threads", name);
    }
    cb_mesh_check_report r;
    st = cb_mesh_check(&r, m1, &err);
    CHECK(st == CB_OK, "%s: check: %s", name, err.msg);
    CHECK(r.closed == 1 && r.boundary_edges == 0, "%s: %d boundary edges", name,
          r.boundary_edges);
    CHECK(r.edge_manifold == 1 && r.vertex_manifold == 1,
          "%s: %d non-manifold edges, %d vertices", name, r.nonmanifold_edges,
          r.nonmanifold_vertices);
    CHECK(r.oriented == 1, "%s: %d misoriented edges", name, r.misoriented_edges);
    CHECK(r.self_intersections == 0, "%s: self-intersections %d", name, r.self_intersections);
    CHECK(r.outward == 1 && r.bounds_volume == 1, "%s: outward %d, bounds a volume %d", name,
          r.outward, r.bounds_volume);
    CHECK(cb_mesh_check_passed(&r), "%s: mesh check failed", name);
    double v = cb_mesh_volume(m1);
    printf("%s: chord %.3g: %d vertices, %d triangles, volume %.10g\n", name, chord,
           m1->n_vertices, m1->n_triangles, v);
    cb_mesh_clear(m1);
    cb_mesh_clear(m2);
    return st == CB_OK ? v : NAN;
}

/* Each STEP model at three times its default tolerance and at the default: within area x
 * chord of the reference volume (each mesh point lies within chord of the surface), and
 * closer at the finer tolerance. (Finer ones: test_fine.) */
static void test_models(void)
{
    for (size_t k = 0; k < sizeof MODELS / sizeof MODELS[0]; k++) {
        cb_topo_body *b = load(MODELS[k].file);
        if (!b)
            continue;
        double u3 = pow(b->length_unit_mm, 3);
        double c = default_chord(b), prev_err = HUGE_VAL;
        for (int level = 0; level < 2; level++) {
            double chord = level ? c : 3 * c;
            double v = check_model(MODELS[k].file, b, chord) * u3;
            double e = fabs(v - MODELS[k].volume);
            double bound = MODELS[k].area * chord * b->length_unit_mm;
            CHECK(e <= bound, "%s: chord %g: volume %.10g, reference %.10g, error %g > %g",
                  MODELS[k].file, chord, v, MODELS[k].volume, e, bound);
            CHECK(e < prev_err, "%s: chord %g: error %g did not shrink from %g", MODELS[k].file,
                  chord, e, prev_err);
            prev_err = e;
        }
        cb_topo_body_free(b);
    }
    cb_topo_body *h = bird();
    if (h) {
        double v = check_model("hummingbird", h, 3 * default_chord(h));
        double w = check_model("hummingbird", h, default_chord(h));
        /* No reference volume: the two meshes must agree to their tolerances. */
        CHECK(fabs(v - w) < 0.02 * w, "hummingbird: volumes %g and %g", v, w);
        cb_topo_body_free(h);
    }
}

/* Smallest area / longest side^2 of m's triangles (0.433 for an equilateral one). */
static double min_shape(const cb_mesh_t m)
{
    double q = HUGE_VAL;
    for (int t = 0; t < m->n_triangles; t++) {
        const double *p[3];
        double e1[3], e2[3], n[3], longest = 0;
        for (int k = 0; k < 3; k++)
            p[k] = m->xyz + 3 * m->tri[3 * t + k];
        for (int k = 0; k < 3; k++) {
            longest = fmax(longest, cb_vec3_dist(p[k], p[(k + 1) % 3]));
            e1[k] = p[1][k] - p[0][k];
            e2[k] = p[2][k] - p[0][k];
        }
        cb_vec3_cross(n, e1, e2);
        q = fmin(q, 0.5 * cb_vec3_norm(n) / (longest * longest));
    }
    return q;
}

/* Tolerances well below the default, where refinement used to chase errors it could not remove
 * into fans of needles against the boundary (area / longest side^2 down to 1e-12, crossing
 * each other in CGAL's eyes): linkrods at 0.3 and 0.1 of its default chord, trj5 at 0.5 (a
 * seam beside a cone-like pole, and B-spline knot lines meeting the boundary), the hummingbird
 * at 0.5. Every mesh must pass every check, keep its triangles above 1e-5 of the equilateral
 * shape (the thinnest left, about 2e-4, join boundary samples of narrow faces, which
 * refinement may not move), and stay within area x chord of the reference volume. */
static void test_fine(void)
{
    static const struct {
        int model; /* in MODELS */
        double scale;
    } runs[] = {{1, 0.3}, {1, 0.1}, {0, 0.5}};
    for (size_t k = 0; k < sizeof runs / sizeof runs[0]; k++) {
        const model_ref *ref = &MODELS[runs[k].model];
        cb_topo_body *b = load(ref->file);
        if (!b)
            continue;
        double chord = runs[k].scale * default_chord(b), u3 = pow(b->length_unit_mm, 3);
        double e = fabs(check_model(ref->file, b, chord) * u3 - ref->volume);
        double bound = ref->area * chord * b->length_unit_mm;
        CHECK(e <= bound, "%s: chord %g: volume error %g > %g", ref->file, chord, e, bound);
        cb_mesh_t m;
        cb_mesh_init(m);
        cb_error err;
        CHECK(tess(m, b, chord, 0, &err) == CB_OK, "%s: %s", ref->file, err.msg);
        double q = min_shape(m);
        CHECK(q > 1e-5, "%s: chord %g: a triangle of shape %g", ref->file, chord, q);
        cb_mesh_clear(m);
        cb_topo_body_free(b);
    }
    cb_topo_body *h = bird();
    if (h) {
        double chord = 0.5 * default_chord(h);
        check_model("hummingbird", h, chord);
        cb_mesh_t m;
        cb_mesh_init(m);
        cb_error err;
        CHECK(tess(m, h, chord, 0, &err) == CB_OK, "hummingbird: %s", err.msg);
        double q = min_shape(m);
        CHECK(q > 1e-5, "hummingbird: chord %g: a triangle of shape %g", chord, q);
        cb_mesh_clear(m);
        cb_topo_body_free(h);
    }
}

/* A user tolerance is honoured: finer means more triangles, and a max_edge bounds the
 * sides. */
static void test_options(void)
{
    cb_topo_body *b = load("ujoint_cross.step");
    if (!b)
        return;
    cb_error err;
    cb_mesh_t m;
    cb_mesh_init(m);
    cb_tess_opts o;
    cb_tess_opts_init(&o);
    o.chord_tol = NAN;
    CHECK(cb_tess_body(m, b, &o, NULL, &err) == CB_ERR_INVALID, "NaN chord_tol accepted");
    CHECK(strstr(err.msg, "chord_tol") != NULL, "message: %s", err.msg);
    cb_tess_opts_init(&o);
    o.angle_tol = 2.0;
    CHECK(cb_tess_body(m, b, &o, NULL, &err) == CB_ERR_INVALID, "angle_tol 2 accepted");
    CHECK(strstr(err.msg, "angle_tol") != NULL, "message: %s", err.msg);
    cb_tess_opts_init(&o);
    o.max_edge = -1;
    CHECK(cb_tess_body(m, b, &o, NULL, &err) == CB_ERR_INVALID, "max_edge -1 accepted");
    CHECK(strstr(err.msg, "max_edge") != NULL, "message: %s", err.msg);
    CHECK(m->n_triangles == 0, "mesh not empty after a failure");

    cb_tess_face_mesh fm;
    cb_tess_face_mesh_init(&fm);
    cb_tess_edges es;
    cb_tess_edges_init(&es);
    cb_tess_opts_init(&o);
    CHECK(cb_tess_opts_resolve(&o, &o, b, &err) == CB_OK, "resolve: %s", err.msg);
    CHECK(cb_tess_edges_sample(&es, b, &o, NULL, &err) == CB_OK, "sample: %s", err.msg);
    CHECK(cb_tess_face(&fm, b, b->n_faces, &es, &o, NULL, &err) == CB_ERR_INVALID,
          "face out of range accepted");
    /* Faces one at a time make the same triangles as the body. */
    long tris = 0;
    for (int f = 0; f < b->n_faces; f++) {
        cb_status st = cb_tess_face(&fm, b, f, &es, &o, NULL, &err);
        CHECK(st == CB_OK, "face %d: %s", f, err.msg);
        tris += fm.n_tris;
    }
    CHECK(cb_tess_body(m, b, NULL, NULL, &err) == CB_OK, "%s", err.msg);
    CHECK(tris == m->n_triangles, "faces one by one: %ld triangles, body: %d", tris,
          m->n_triangles);
    cb_tess_face_mesh_clear(&fm);
    cb_tess_edges_clear(&es);

    int coarse = m->n_triangles;
    cb_tess_opts_init(&o);
    o.chord_tol = 0.01;
    CHECK(cb_tess_body(m, b, &o, NULL, &err) == CB_OK, "%s", err.msg);
    CHECK(m->n_triangles > 4 * coarse, "chord 0.01: %d triangles, default: %d", m->n_triangles,
          coarse);

    cb_tess_opts_init(&o);
    o.max_edge = 5;
    CHECK(cb_tess_body(m, b, &o, NULL, &err) == CB_OK, "%s", err.msg);
    double longest = 0;
    for (int t = 0; t < m->n_triangles; t++)
        for (int k = 0; k < 3; k++)
            longest = fmax(longest, cb_vec3_dist(m->xyz + 3 * m->tri[3 * t + k],
                                                 m->xyz + 3 * m->tri[3 * t + (k + 1) % 3]));
    CHECK(longest <= 2 * o.max_edge, "max_edge 5: a side of %g", longest);
    cb_mesh_clear(m);
    cb_topo_body_free(b);
}

static void cancel_at_once(void *user, double fraction, const char *stage)
{
    (void)fraction;
    (void)stage;
    cb_context_cancel(user);
}

static void test_cancel(void)
{
    cb_topo_body *b = load("trj5_k1-al-214.stp");
    if (!b)
        return;
    cb_context ctx;
    cb_context_init(&ctx);
    ctx.progress = cancel_at_once;
    ctx.user = &ctx;
    cb_mesh_t m;
    cb_mesh_init(m);
    cb_error err;
    cb_status st = cb_tess_body(m, b, NULL, &ctx, &err);
    CHECK(st == CB_ERR_CANCELLED, "status %d (%s)", st, err.msg);
    CHECK(m->n_triangles == 0 && m->n_vertices == 0, "cancelled run left %d triangles",
          m->n_triangles);
    cb_mesh_clear(m);
    cb_topo_body_free(b);
}

/* The mesh of b at chord tolerance `chord` alone (angular tolerance pi/2, its largest, so
 * that the chord decides the refinement), checked; its volume, NaN when it fails. */
static double chord_mesh_volume(const char *name, const cb_topo_body *b, double chord)
{
    cb_tess_opts o;
    cb_tess_opts_init(&o);
    o.chord_tol = chord;
    o.angle_tol = 0.5 * 3.14159265358979323846;
    cb_mesh_t m;
    cb_mesh_init(m);
    cb_error err;
    cb_mesh_check_report r;
    cb_status st = cb_tess_body(m, b, &o, NULL, &err);
    if (!st)
        st = cb_mesh_check(&r, m, &err);
    CHECK(st == CB_OK && cb_mesh_check_passed(&r), "%s: chord %g: %s", name, chord,
          st ? err.msg : "mesh check failed");
    double v = !st && cb_mesh_check_passed(&r) ? cb_mesh_volume(m) : NAN;
    cb_mesh_clear(m);
    return v;
}

/* The primitives with analytic and with B-spline faces: at chord tolerances c, c / 4, c / 16
 * (c = 1e-2 of the box diagonal) every mesh passes the checks and its volume approaches the
 * closed form from the mesh side within area x chord, by an order close to 1 in the
 * tolerance (a chord's sagitta is what the tolerance bounds); the orders are printed. */
static void test_primitives(void)
{
    static const char *const names[6] = {"box", "sphere", "ellipsoid", "cylinder", "cone",
                                         "torus"};
    const double PI = 3.14159265358979323846, lo[3] = {-1, -0.5, 0.25}, hi[3] = {2, 1.5, 1.25};
    /* Closed-form volumes and areas of the shapes built below. */
    const double sl = sqrt(0.25 + 1.5 * 1.5); /* the frustum's slant height */
    const double vol[6] = {3 * 2 * 1, 4 * PI * 1.5 * 1.5 * 1.5 / 3, 4 * PI * 2 * 1 * 0.5 / 3,
                           PI * 0.75 * 0.75 * 2, PI * 1.5 * (1 + 1 * 0.5 + 0.25) / 3,
                           2 * PI * PI * 2 * 0.5 * 0.5};
    const double area_bound[6] = {22, 4 * PI * 1.5 * 1.5, 4 * PI * 2 * 1, /* >= the areas */
                                  2 * PI * 0.75 * (0.75 + 2), PI * (1 + 0.25 + 1.5 * sl),
                                  4 * PI * PI * 2 * 0.5};
    for (int shape = 0; shape < 6; shape++)
        for (int as_nurbs = 0; as_nurbs < 2; as_nurbs++) {
            cb_topo_body *b = NULL;
            cb_error err;
            cb_status st;
            switch (shape) {
            case 0: st = cb_prim_box(&b, NULL, lo, hi, as_nurbs, 0, &err); break;
            case 1: st = cb_prim_sphere(&b, NULL, 1.5, as_nurbs, 0, &err); break;
            case 2: st = cb_prim_ellipsoid(&b, NULL, 2, 1, 0.5, as_nurbs, 0, &err); break;
            case 3: st = cb_prim_cylinder(&b, NULL, 0.75, 2, as_nurbs, 0, &err); break;
            case 4: st = cb_prim_cone(&b, NULL, 1, 0.5, 1.5, as_nurbs, 0, &err); break;
            default: st = cb_prim_torus(&b, NULL, 2, 0.5, as_nurbs, 0, &err); break;
            }
            CHECK(st == CB_OK, "%s: %s", names[shape], err.msg);
            if (st)
                continue;
            char name[64];
            snprintf(name, sizeof name, "%s%s", names[shape], as_nurbs ? " (B-spline)" : "");
            double c = 10 * default_chord(b), e[3] = {0, 0, 0};
            for (int k = 0; k < 3; k++) {
                double chord = c / pow(4, k), v = chord_mesh_volume(name, b, chord);
                e[k] = fabs(v - vol[shape]) / vol[shape];
                CHECK(fabs(v - vol[shape]) <= area_bound[shape] * chord,
                      "%s: chord %g: mesh volume %.12g, exact %.12g", name, chord, v,
                      vol[shape]);
            }
            if (shape == 0) {
                CHECK(e[0] < 1e-13 && e[1] < 1e-13 && e[2] < 1e-13,
                      "box: mesh volume off by %g, %g, %g", e[0], e[1], e[2]);
            } else {
                double o1 = log(e[0] / e[1]) / log(4), o2 = log(e[1] / e[2]) / log(4);
                CHECK(o1 > 0.75 && o2 > 0.75 && o1 < 1.5 && o2 < 1.5,
                      "%s: volume error %.3g, %.3g, %.3g: orders %.2f, %.2f in the tolerance",
                      name, e[0], e[1], e[2], o1, o2);
                printf("%s: mesh volume error %.2e, %.2e, %.2e at chord / 1, 4, 16: orders "
                       "%.2f, %.2f\n",
                       name, e[0], e[1], e[2], o1, o2);
            }
            cb_topo_body_free(b);
        }
}

int main(void)
{
    test_options();
    test_cancel();
    test_primitives();
    test_models();
    test_fine();
    return check_report("test_brep_tess");
}
