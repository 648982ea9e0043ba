/* Mass properties (brep/mass.c): every primitive (brep/prim.h), analytic and B-spline faces,
 * in several poses, against closed-form volume, area and centroid; the shipped STEP models
 * against Open CASCADE's reference figures (models/SOURCES.md), with the files' pcurves and
 * with pcurves fitted from scratch; 1 and 2 threads bit-identical; cancellation; bad input. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brep/mass.h"
#include "brep/prim.h"
#include "check.h"
#include "io/step.h"

static const double PI = 3.14159265358979323846;

static const char *shared_dir(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    return d ? d : "../shared";
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---------------------------------------------------------------- ellipsoid area ----------- */

/* Carlson's symmetric integrals R_F and R_D by duplication (Carlson 1995), to round-off. */
static double carlson_rf(double x, double y, double z)
{
    for (;;) {
        double sx = sqrt(x), sy = sqrt(y), sz = sqrt(z), l = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        z = 0.25 * (z + l);
        double mu = (x + y + z) / 3, dx = 1 - x / mu, dy = 1 - y / mu, dz = 1 - z / mu;
        if (fmax(fabs(dx), fmax(fabs(dy), fabs(dz))) < 1e-4) {
            double e2 = dx * dy - dz * dz, e3 = dx * dy * dz;
            return (1 - e2 / 10 + e3 / 14 + e2 * e2 / 24 - 3 * e2 * e3 / 44) / sqrt(mu);
        }
    }
}

static double carlson_rd(double x, double y, double z)
{
    double sum = 0, fac = 1;
    for (;;) {
        double sx = sqrt(x), sy = sqrt(y), sz = sqrt(z), l = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + l));
        fac *= 0.25;
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        z = 0.25 * (z + l);
        double mu = 0.2 * (x + y + 3 * z), dx = (mu - x) / mu, dy = (mu - y) / mu,
               dz = (mu - z) / mu;
        if (fmax(fabs(dx), fmax(fabs(dy), fabs(dz))) < 1e-4) {
            double ea = dx * dy, eb = dz * dz, ec = ea - eb, ed = ea - 6 * eb, ee = ed + 2 * ec;
            double c1 = 3.0 / 14, c2 = 1.0 / 6, c3 = 9.0 / 22, c4 = 3.0 / 26, c5 = 0.25 * c3,
                   c6 = 1.5 * c4;
            return 3 * sum + fac *
                                 (1 + ed * (-c1 + c5 * ed - c6 * dz * ee) +
                                  dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea))) /
                                 (mu * sqrt(mu));
        }
    }
}

/* Area of the ellipsoid with semi-axes a >= b >= c (a > c): 2 pi c^2 + 2 pi a b / sin(phi)
 * (E(phi, k) sin^2 phi + F(phi, k) cos^2 phi), cos phi = c / a,
 * k^2 = a^2 (b^2 - c^2) / (b^2 (a^2 - c^2)), with F and E by Carlson's forms. */
static double ellipsoid_area(double a, double b, double c)
{
    double cp = c / a, sp = sqrt(1 - cp * cp),
           k2 = a * a * (b * b - c * c) / (b * b * (a * a - c * c));
    double y = 1 - k2 * sp * sp, rf = carlson_rf(cp * cp, y, 1), rd = carlson_rd(cp * cp, y, 1);
    double F = sp * rf, E = sp * rf - k2 * sp * sp * sp * rd / 3;
    return 2 * PI * c * c + 2 * PI * a * b / sp * (E * sp * sp + F * cp * cp);
}

/* The formula above against the closed forms of the spheroids (a check of the reference). */
static void check_ellipsoid_area_formula(void)
{
    double a = 2, c = 0.5, e = sqrt(1 - c * c / (a * a));
    double oblate = 2 * PI * a * a * (1 + (1 - e * e) / e * atanh(e));
    double prolate = 2 * PI * c * c * (1 + a / (c * e) * asin(e));
    double fo = ellipsoid_area(a, a, c), fp = ellipsoid_area(a, c, c);
    CHECK(fabs(fo - oblate) < 1e-13 * oblate, "oblate spheroid area %.17g, closed form %.17g", fo,
          oblate);
    CHECK(fabs(fp - prolate) < 1e-13 * prolate, "prolate spheroid area %.17g, closed form %.17g",
          fp, prolate);
}

/* ---------------------------------------------------------------- primitives --------------- */

enum { BOX, SPHERE, ELLIPSOID, CYLINDER, FRUSTUM, CONE_UP, CONE_DOWN, TORUS, N_SHAPES };

static const char *const shape_name[N_SHAPES] = {
    "box",     "sphere",         "ellipsoid",        "cylinder",
    "frustum", "cone (apex up)", "cone (apex down)", "torus"};

/* Builds the shape and its closed-form volume, area and centroid in local coordinates. */
static cb_status build(cb_topo_body **b, double ref[5], int shape, const cb_frame *f, int as_nurbs,
                       cb_error *err)
{
    const double lo[3] = {-1, -0.5, 0.25}, hi[3] = {2, 1.5, 1.25};
    double r0 = 1, r1 = 0.5, h = 1.5;
    ref[2] = ref[3] = ref[4] = 0;
    switch (shape) {
    case BOX:
        ref[0] = 3 * 2 * 1;
        ref[1] = 2 * (3 * 2 + 2 * 1 + 1 * 3);
        ref[2] = 0.5;
        ref[3] = 0.5;
        ref[4] = 0.75;
        return cb_prim_box(b, f, lo, hi, as_nurbs, 0, err);
    case SPHERE:
        ref[0] = 4 * PI / 3 * 1.5 * 1.5 * 1.5;
        ref[1] = 4 * PI * 1.5 * 1.5;
        return cb_prim_sphere(b, f, 1.5, as_nurbs, 0, err);
    case ELLIPSOID:
        ref[0] = 4 * PI / 3 * 2 * 1 * 0.5;
        ref[1] = ellipsoid_area(2, 1, 0.5);
        return cb_prim_ellipsoid(b, f, 2, 1, 0.5, as_nurbs, 0, err);
    case CYLINDER:
        ref[0] = PI * 0.75 * 0.75 * 2;
        ref[1] = 2 * PI * 0.75 * 2 + 2 * PI * 0.75 * 0.75;
        ref[4] = 1;
        return cb_prim_cylinder(b, f, 0.75, 2, as_nurbs, 0, err);
    case CONE_UP: r1 = 0, h = 2, r0 = 1.25; break;
    case CONE_DOWN: r0 = 0, h = 2, r1 = 1.25; break;
    case TORUS:
        ref[0] = 2 * PI * PI * 2 * 0.5 * 0.5;
        ref[1] = 4 * PI * PI * 2 * 0.5;
        return cb_prim_torus(b, f, 2, 0.5, as_nurbs, 0, err);
    default: break;
    }
    double s = r0 * r0 + r0 * r1 + r1 * r1;
    ref[0] = PI * h / 3 * s;
    ref[1] = PI * (r0 + r1) * hypot(r0 - r1, h) + PI * (r0 * r0 + r1 * r1);
    ref[4] = h * (r0 * r0 + 2 * r0 * r1 + 3 * r1 * r1) / (4 * s);
    return cb_prim_cone(b, f, r0, r1, h, as_nurbs, 0, err);
}

static void random_frame(cb_frame *f, check_rng *rng, int pose)
{
    double o[3], z[3], x[3];
    for (int i = 0; i < 3; i++) {
        o[i] = pose ? check_rng_uniform(rng, -20, 20) : 0;
        z[i] = pose ? check_rng_uniform(rng, -1, 1) : i == 2;
        x[i] = pose ? check_rng_uniform(rng, -1, 1) : i == 0;
    }
    cb_error err;
    CHECK(cb_frame_make(f, o, z, x, &err) == CB_OK, "frame: %s", err.msg);
}

static void check_primitive(int shape, int as_nurbs, const cb_frame *f, int pose)
{
    cb_topo_body *b = NULL;
    cb_error err;
    double ref[5];
    cb_status st = build(&b, ref, shape, f, as_nurbs, &err);
    CHECK(st == CB_OK, "%s: %s", shape_name[shape], err.msg);
    if (st)
        return;
    cb_mass_props m;
    double t = now();
    st = cb_mass_body(&m, b, 0, NULL, &err);
    t = now() - t;
    CHECK(st == CB_OK, "%s nurbs %d pose %d: %s", shape_name[shape], as_nurbs, pose, err.msg);
    double ev = fabs(m.volume - ref[0]) / ref[0], ea = fabs(m.area - ref[1]) / ref[1];
    double c[3], l[3] = {ref[2], ref[3], ref[4]};
    cb_frame_to_world(c, f, l);
    double ec = cb_vec3_dist(c, m.centroid);
    CHECK(!st && ev <= 1e-9 && ea <= 1e-9 && ec <= 1e-9,
          "%s nurbs %d pose %d: volume %.17g (exact %.17g, rel %.3g), area %.17g (exact %.17g, "
          "rel %.3g), centroid off by %.3g",
          shape_name[shape], as_nurbs, pose, m.volume, ref[0], ev, m.area, ref[1], ea, ec);
    /* closed: the normals integrate to zero */
    CHECK(!st && cb_vec3_norm(m.vector_area) <= 1e-9 * m.area,
          "%s nurbs %d pose %d: vector area %.3g of area %.6g", shape_name[shape], as_nurbs, pose,
          cb_vec3_norm(m.vector_area), m.area);
    /* The area alone (what a surface model has): the same, its check (Stokes) passing. */
    double area = 0;
    cb_status sa = st ? st : cb_mass_area(&area, b, 0, NULL, &err);
    CHECK(!sa && fabs(area - m.area) <= 1e-12 * m.area, "%s nurbs %d pose %d: cb_mass_area %.17g "
          "against %.17g (%s)", shape_name[shape], as_nurbs, pose, area, m.area, sa ? err.msg : "");
    /* A plane face whose loops run backwards (its region integrated with the wrong sign)
     * leaves twice its vector area: what the check of Boolean results relies on
     * (cli/result.c). */
    int plane = -1;
    for (int k = 0; k < b->n_faces && plane < 0; k++) {
        const cb_topo_surface *sf = b->surfaces + b->faces[k].surface;
        if (sf->kind == CB_SURFACE_ANALYTIC && sf->analytic.kind == CB_ANALYTIC_PLANE)
            plane = k;
    }
    if (!st && plane >= 0) {
        /* its loops run backwards: coedges in reverse order, each the other way along its
         * edge */
        const cb_topo_face *fc = b->faces + plane;
        for (int l = fc->first; l < fc->first + fc->count; l++) {
            cb_topo_coedge *c = b->coedges + b->loops[l].first;
            for (int i = 0, j = b->loops[l].count - 1; i < j; i++, j--) {
                cb_topo_coedge t = c[i];
                c[i] = c[j];
                c[j] = t;
            }
            for (int i = 0; i < b->loops[l].count; i++)
                c[i].sense = !c[i].sense;
        }
        st = cb_topo_body_index(b, &err);
        CHECK(st == CB_OK, "%s: index: %s", shape_name[shape], err.msg);
    }
    if (!st && plane >= 0) {
        cb_mass_props m2;
        st = cb_mass_body(&m2, b, 0, NULL, &err);
        CHECK(st == CB_OK && cb_vec3_norm(m2.vector_area) > 1e-3 * m.area,
              "%s nurbs %d pose %d: one face turned, vector area %.3g of area %.6g (%s)",
              shape_name[shape], as_nurbs, pose, st ? NAN : cb_vec3_norm(m2.vector_area),
              m.area, st ? err.msg : "");
        /* and the area alone refuses it: the normals do not match the (empty) boundary */
        sa = cb_mass_area(&area, b, 0, NULL, &err);
        CHECK(sa == CB_ERR_NUMERIC && strstr(err.msg, "do not match its boundary"),
              "%s nurbs %d pose %d: one face turned, cb_mass_area %s (%s)", shape_name[shape],
              as_nurbs, pose, cb_status_name(sa), sa ? err.msg : "accepted");
    }
    printf("%-17s %-8s pose %d: volume rel err %.2e, area %.2e, centroid %.2e, %.3f s\n",
           shape_name[shape], as_nurbs ? "B-spline" : "analytic", pose, ev, ea, ec, t);
    cb_topo_body_free(b);
}

/* ---------------------------------------------------------------- edges off their faces ---- */

/* A face is trimmed at the foot points of its edges on its surface, and the loop integral must
 * follow them. A torus whose four circles (two meridians, the halves of the outer equator)
 * are widened by d about their centres, within tolerance, has the same foot points, so its
 * area stays 4 pi^2 R r. Taken with the least-squares derivative of the foot points instead of
 * their true one, the loop integral along the meridians counts (r + d) / r times too much. */
static void check_edges_off_faces(void)
{
    const double big = 3, small = 1, d = 1e-4;
    cb_topo_body *b = NULL;
    cb_error err;
    if (cb_prim_torus(&b, NULL, big, small, 0, 10 * d, &err)) {
        CHECK(0, "torus: %s", err.msg);
        return;
    }
    int widened = 0;
    for (int e = 0; e < b->n_edges; e++) {
        cb_topo_curve *c = &b->curves[b->edges[e].curve];
        if (c->kind == CB_CURVE_CIRCLE) {
            c->r1 += d;
            c->r2 += d;
            widened++;
        }
        b->edges[e].tol = 10 * d;
    }
    CHECK(widened == 4, "%d circles widened, 4 expected", widened);
    cb_mass_props m;
    cb_status st = cb_mass_body(&m, b, 0, NULL, &err);
    CHECK(st == CB_OK, "torus with widened circles: %s", err.msg);
    double area = 4 * PI * PI * big * small, ea = fabs(m.area - area) / area;
    CHECK(!st && ea <= 1e-10, "torus, circles off by %g: area %.17g, exact %.17g (rel %.3g)", d,
          m.area, area, ea);
    printf("torus, circles off by %g: area rel err %.2e\n", d, ea);
    cb_topo_body_free(b);
}

/* ---------------------------------------------------------------- models ------------------- */

/* trj5's edges lie up to 1.75e-4 cm off their B-spline faces. Each face is trimmed at the foot
 * points of its edges; Open CASCADE trims at its healed pcurves, which approximate those foot
 * points, and the two differ by about 1.3e-7 of the volume (per face up to 3e-4 mm^3, all on
 * faces whose edges it gives tolerances near 1e-3 mm). The volume of a shell that does not
 * close exactly also depends on the reference point (here by 6e-8 between the edge box centre
 * and OCCT's vertex mean). Both stay well inside 1e-6. */
typedef struct {
    const char *file;
    double volume, area; /* mm^3, mm^2 (models/SOURCES.md) */
    double volume_tol;   /* relative */
} model_case;

static const model_case models[] = {{"trj5_k1-al-214.stp", 7936.1475, 4952.8495, 1e-6},
                                    {"linkrods.step", 3.847013, 32.151437, 1e-6},
                                    {"ujoint_fork.step", 81046.104, 23955.819, 1e-6},
                                    {"ujoint_cross.step", 95097.336, 14307.078, 1e-6}};

static cb_topo_body *load(const char *file)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/%s", shared_dir(), file);
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = cb_step_read(&b, path, &err);
    CHECK(st == CB_OK && b, "%s: %s", file, err.msg);
    if (!st) {
        int dropped;
        st = cb_topo_repair_pcurves(b, b->tol, 17, &dropped, &err);
        CHECK(st == CB_OK, "%s: repair: %s", file, err.msg);
    }
    if (st) {
        cb_topo_body_free(b);
        return NULL;
    }
    return b;
}

static void check_model_props(const model_case *mc, const cb_topo_body *b, const char *how,
                              double rel_tol)
{
    cb_mass_props m;
    cb_error err;
    double t = now();
    cb_status st = cb_mass_body(&m, b, rel_tol, NULL, &err);
    t = now() - t;
    CHECK(st == CB_OK, "%s (%s): %s", mc->file, how, err.msg);
    if (st)
        return;
    double u = b->length_unit_mm, v = m.volume * u * u * u, a = m.area * u * u;
    double ev = fabs(v - mc->volume) / mc->volume, ea = fabs(a - mc->area) / mc->area;
    /* closed up to the gaps the tolerance allows (the bound of cli/result.c) */
    double len = 0;
    for (int e = 0; e < b->n_edges; e++)
        len += cb_topo_edge_length(b, e);
    CHECK(cb_vec3_norm(m.vector_area) <= 2 * b->tol * len + 1e-9 * m.area,
          "%s (%s): vector area %.3g, tolerance %g, edges %.6g long", mc->file, how,
          cb_vec3_norm(m.vector_area), b->tol, len);
    CHECK(ev <= mc->volume_tol && ea <= 1e-6,
          "%s (%s): volume %.10g mm^3 (reference %.10g, rel %.3g), area %.10g mm^2 (reference "
          "%.10g, rel %.3g)",
          mc->file, how, v, mc->volume, ev, a, mc->area, ea);
    printf("%-20s %-16s volume %.10g (rel %.2e), area %.10g (rel %.2e), %.2f s\n", mc->file, how, v,
           ev, a, ea, t);
}

static void check_model(const model_case *mc)
{
    cb_topo_body *b = load(mc->file);
    if (!b)
        return;
    check_model_props(mc, b, "file pcurves", 1e-8);
    /* Pcurves fitted afresh, coarsely: the result must not depend on the fit. */
    for (int c = 0; c < b->n_coedges; c++)
        b->coedges[c].pcurve = -1;
    cb_error err;
    cb_status st = cb_topo_compute_pcurves(b, 10 * b->tol, &err);
    CHECK(st == CB_OK, "%s: pcurves: %s", mc->file, err.msg);
    if (!st)
        check_model_props(mc, b, "fitted pcurves", 1e-8);
    cb_topo_body_free(b);
}

/* Surface models of the STEP corpus (open shells, no solid, as CAD systems write sheets):
 * cb_mass_body refuses them, cb_mass_area gives their area, checked by the boundary (Stokes;
 * its refusal of a face integrated over the wrong region: check_primitive's turned face). Areas:
 * Open CASCADE's (../shared/corpus/occt-reference.json). bm2_pe_t4-A.stp writes its tori's
 * pcurves in degrees: read as radians, a torus face came out 1.2e6 mm^2 off and the check
 * refused it. */
static void check_surface_models(void)
{
    static const struct {
        const char *file;
        double area; /* mm^2 */
    } cases[] = {{"trj7_c2-ct-214.stp", 3500},
                 {"trj8_c2-pe-203.stp", 99728837.684},
                 {"OCC22459-TEST2.stp", 16167658.80271},
                 {"bm2_pe_t4-A.stp", 2523816.887356674}};
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/corpus/step/%s", shared_dir(), cases[k].file);
        cb_topo_body *b = NULL;
        cb_error err;
        cb_status st = cb_step_read(&b, path, &err);
        CHECK(st == CB_OK, "%s: %s", cases[k].file, err.msg);
        if (st)
            continue;
        cb_mass_props m;
        CHECK(cb_mass_body(&m, b, 0, NULL, &err) == CB_ERR_INVALID,
              "%s: a surface model's volume integrated", cases[k].file);
        double area = 0, u = b->length_unit_mm;
        st = cb_mass_area(&area, b, 1e-9, NULL, &err);
        CHECK(st == CB_OK && fabs(area * u * u - cases[k].area) <= 1e-6 * cases[k].area,
              "%s: area %.10g mm^2, Open CASCADE %.10g (%s)", cases[k].file, area * u * u,
              cases[k].area, st ? err.msg : "");
        printf("%-20s area %.10g mm^2 %s\n", cases[k].file, area * u * u,
               st ? err.msg : "");
        cb_topo_body_free(b);
    }
}

/* ---------------------------------------------------------------- threads, cancel, errors -- */

static void check_threads(void)
{
    cb_topo_body *b = load("trj5_k1-al-214.stp");
    if (!b)
        return;
    cb_mass_props m1, m2;
    cb_context c1, c2;
    cb_context_init(&c1);
    cb_context_init(&c2);
    c1.threads = 1;
    c2.threads = 2;
    cb_error err;
    cb_status s1 = cb_mass_body(&m1, b, 1e-6, &c1, &err),
              s2 = cb_mass_body(&m2, b, 1e-6, &c2, &err);
    CHECK(s1 == CB_OK && s2 == CB_OK && memcmp(&m1, &m2, sizeof m1) == 0,
          "1 and 2 threads differ: volume %.17g vs %.17g, area %.17g vs %.17g", m1.volume,
          m2.volume, m1.area, m2.area);
    cb_topo_body_free(b);
}

typedef struct {
    cb_context *ctx;
    int calls;
    double last;
    int monotone;
} progress_log;

static void on_progress(void *user, double fraction, const char *stage)
{
    progress_log *p = user;
    p->monotone &= fraction >= p->last && fraction <= 1 && strcmp(stage, "mass properties") == 0;
    p->last = fraction;
    if (++p->calls == 2)
        cb_context_cancel(p->ctx);
}

static void check_cancel(void)
{
    cb_topo_body *b = NULL;
    cb_error err;
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 2, 3};
    if (cb_prim_box(&b, NULL, lo, hi, 1, 0, &err)) {
        CHECK(0, "box: %s", err.msg);
        return;
    }
    cb_context ctx;
    cb_context_init(&ctx);
    ctx.threads = 1;
    progress_log log = {&ctx, 0, 0, 1};
    ctx.progress = on_progress;
    ctx.user = &log;
    cb_mass_props m;
    cb_status st = cb_mass_body(&m, b, 0, &ctx, &err);
    CHECK(st == CB_ERR_CANCELLED && log.calls == 2 && log.monotone,
          "cancel from the progress callback: status %d (%s) after %d calls", st, err.msg,
          log.calls);
    /* Without cancelling: progress reaches 1 and never decreases. */
    cb_context_init(&ctx);
    log = (progress_log){NULL, 0, 0, 1};
    ctx.progress = on_progress;
    ctx.user = &log;
    log.calls = 10;
    st = cb_mass_body(&m, b, 0, &ctx, &err);
    CHECK(st == CB_OK && log.monotone && log.last == 1, "progress: status %d, last %g", st,
          log.last);
    cb_topo_body_free(b);
}

static void check_errors(void)
{
    cb_topo_body *b = NULL;
    cb_error err;
    if (cb_prim_cylinder(&b, NULL, 1, 2, 0, 0, &err)) {
        CHECK(0, "cylinder: %s", err.msg);
        return;
    }
    cb_mass_props m;
    cb_status st = cb_mass_body(&m, b, NAN, NULL, &err);
    CHECK(st == CB_ERR_INVALID && strstr(err.msg, "NaN"), "NaN tolerance: %d %s", st, err.msg);
    st = cb_mass_shell(&m, b, 3, 0, NULL, &err);
    CHECK(st == CB_ERR_INVALID && strstr(err.msg, "out of range"), "shell 3: %d %s", st, err.msg);
    /* A face without pcurves. */
    int keep = b->coedges[4].pcurve;
    b->coedges[4].pcurve = -1;
    st = cb_mass_body(&m, b, 0, NULL, &err);
    CHECK(st == CB_ERR_INVALID && strstr(err.msg, "coedge 4 has no pcurve"), "no pcurve: %d %s", st,
          err.msg);
    b->coedges[4].pcurve = keep;
    /* The top disc moved to a shell of its own: both shells are open. */
    int s = cb_topo_body_add_shell(b);
    b->shells[0].count = 2;
    b->shells[s] = (cb_topo_shell){2, 1, 0, -1};
    b->faces[2].shell = s;
    st = cb_topo_body_index(b, &err);
    CHECK(st == CB_OK, "index: %s", err.msg);
    st = cb_mass_shell(&m, b, 0, 0, NULL, &err);
    CHECK(st == CB_ERR_INVALID && strstr(err.msg, "shell 0 is open"), "open shell: %d %s", st,
          err.msg);
    cb_topo_body_free(b);
}

/* cb_mass_closure_bound: every primitive in a random pose closes up within it (at the body's
 * tolerance and at the edges'). A box with one face's plane tilted by 1e-3 about the face's
 * centre and that face's edges given a tolerance of 1e-2 (as the STEP reader raises it where
 * a file's faces stray from their edges): the face is integrated between the foot points of
 * its edges on the tilted plane and its normal no longer cancels the others' (vector area
 * about 1e-3 of the face's area): beyond the bound at the body's tolerance, within it at the
 * edges'. */
static void check_closure(void)
{
    check_rng rng = {91};
    for (int shape = 0; shape < N_SHAPES; shape++) {
        cb_frame f;
        random_frame(&f, &rng, 1);
        cb_topo_body *b = NULL;
        double ref[5];
        cb_error err;
        cb_mass_props m;
        if (build(&b, ref, shape, &f, shape % 2, &err) ||
            cb_mass_body(&m, b, 0, NULL, &err)) {
            CHECK(0, "closure %s: %s", shape_name[shape], err.msg);
            cb_topo_body_free(b);
            continue;
        }
        double va = cb_vec3_norm(m.vector_area);
        CHECK(va <= cb_mass_closure_bound(b, m.area, 0) &&
                  va <= cb_mass_closure_bound(b, m.area, 1),
              "closure %s: vector area %.3g, bound %.3g", shape_name[shape], va,
              cb_mass_closure_bound(b, m.area, 0));
        if (shape == BOX) {
            cb_frame *fr = &b->surfaces[b->faces[0].surface].analytic.frame;
            double c = cos(1e-3), sn = sin(1e-3), y[3], z[3];
            for (int i = 0; i < 3; i++) {
                y[i] = c * fr->y[i] + sn * fr->z[i];
                z[i] = c * fr->z[i] - sn * fr->y[i];
            }
            memcpy(fr->y, y, sizeof y);
            memcpy(fr->z, z, sizeof z);
            const cb_topo_loop *lp = &b->loops[b->faces[0].first];
            for (int k = lp->first; k < lp->first + lp->count; k++)
                b->edges[b->coedges[k].edge].tol = 1e-2;
            cb_status st = cb_mass_body(&m, b, 0, NULL, &err);
            va = cb_vec3_norm(m.vector_area);
            CHECK(st == CB_OK && va > cb_mass_closure_bound(b, m.area, 0) &&
                      va <= cb_mass_closure_bound(b, m.area, 1),
                  "closure: a box with a face tilted: %s, vector area %.3g, bounds %.3g %.3g",
                  st ? err.msg : "", va, cb_mass_closure_bound(b, m.area, 0),
                  cb_mass_closure_bound(b, m.area, 1));
        }
        cb_topo_body_free(b);
    }
}

int main(void)
{
    check_ellipsoid_area_formula();
    check_rng rng = {77};
    double t = now();
    for (int shape = 0; shape < N_SHAPES; shape++)
        for (int as_nurbs = 0; as_nurbs < 2; as_nurbs++)
            for (int pose = 0; pose < 2; pose++) {
                cb_frame f;
                random_frame(&f, &rng, pose);
                check_primitive(shape, as_nurbs, &f, pose);
            }
    printf("primitives: %.2f s\n", now() - t);
    check_edges_off_faces();
    for (size_t k = 0; k < sizeof models / sizeof *models; k++) {
        t = now();
        check_model(&models[k]);
        printf("%s: %.2f s in all\n", models[k].file, now() - t);
    }
    check_surface_models();
    check_threads();
    check_cancel();
    check_errors();
    check_closure();
    return check_report("test_brep_mass");
}
