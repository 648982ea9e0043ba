/* Broad phase and point classification (boolean/bool.h): the BVH against brute force, face
 * pairs of two posed hummingbirds against all pairs of boxes, point in solid against exact
 * membership for primitive solids (analytic and rational B-spline faces) and a solid with a
 * void, points on and beside the faces of the shipped models, the fraction of random points
 * inside against the reference volumes, bad input. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "boolean/bool.h"
#include "brep/prim.h"
#include "check.h"
#include "io/step.h"
#include "models/models.h"

static const char *shared_dir(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    return d ? d : "../shared";
}

static cb_topo_body *load(const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/%s", shared_dir(), name);
    cb_topo_body *b = NULL;
    cb_error err;
    CHECK(cb_step_read(&b, path, &err) == CB_OK, "%s: %s", name, err.msg);
    return b;
}

static cb_topo_body *bird(const cb_hummingbird_params *p)
{
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = cb_model_hummingbird(&b, p, &err);
    if (!st)
        st = cb_topo_compute_pcurves(b, 10 * b->tol, &err);
    CHECK(st == CB_OK, "hummingbird: %s", err.msg);
    return b;
}

/* ---------------------------------------------------------------- BVH ---------------------- */

static void random_box(cb_aabb *b, check_rng *rng, double size)
{
    for (int i = 0; i < 3; i++) {
        double c = check_rng_uniform(rng, 0, 10), h = check_rng_uniform(rng, 0, size);
        b->lo[i] = c - h;
        b->hi[i] = c + h;
    }
}

static int seg_box(const cb_aabb *b, const double o[3], const double d[3], double s1, double tol)
{
    /* Dense sampling is not exact; the slab test is, written out independently here. */
    double lo = 0, hi = s1;
    for (int i = 0; i < 3; i++) {
        double a = b->lo[i] - tol, c = b->hi[i] + tol;
        if (d[i] == 0) {
            if (o[i] < a || o[i] > c)
                return 0;
            continue;
        }
        double ta = (a - o[i]) / d[i], tc = (c - o[i]) / d[i];
        if (ta > tc) {
            double x = ta;
            ta = tc;
            tc = x;
        }
        lo = ta > lo ? ta : lo;
        hi = tc < hi ? tc : hi;
    }
    return lo <= hi;
}

static void test_bvh(void)
{
    check_rng rng = {3};
    enum { N = 700 };
    cb_aabb *boxes = malloc(N * sizeof *boxes);
    int *out = malloc(N * sizeof *out);
    for (int k = 0; k < N; k++)
        random_box(&boxes[k], &rng, 0.4);
    cb_bool_bvh t;
    cb_error err;
    CHECK(cb_bool_bvh_init(&t, boxes, N, &err) == CB_OK, "%s", err.msg);
    int wrong = 0, found = 0;
    for (int q = 0; q < 300; q++) {
        cb_aabb b;
        random_box(&b, &rng, 1.5);
        double tol = q % 3 ? 0 : 0.1;
        int n = cb_bool_bvh_query_box(out, N, &t, &b, tol), m = 0, ok = 1;
        for (int k = 0; k < N; k++)
            if (cb_aabb_overlap(&boxes[k], &b, tol)) {
                ok &= m < n && out[m] == k;
                m++;
            }
        found += n;
        wrong += !ok || m != n;
    }
    for (int q = 0; q < 300; q++) {
        double o[3], d[3];
        for (int i = 0; i < 3; i++) {
            o[i] = check_rng_uniform(&rng, -2, 12);
            d[i] = check_rng_uniform(&rng, -1, 1);
        }
        if (q % 10 == 0)
            d[q % 3] = 0;
        double len = check_rng_uniform(&rng, 1, 20);
        int n = cb_bool_bvh_query_ray(out, N, &t, o, d, 0, len, 0.01), m = 0, ok = 1;
        for (int k = 0; k < N; k++)
            if (seg_box(&boxes[k], o, d, len, 0.01)) {
                ok &= m < n && out[m] == k;
                m++;
            }
        found += n;
        wrong += !ok || m != n;
    }
    CHECK(wrong == 0 && found > 1000, "bvh: %d of 600 queries differ from brute force (%d found)",
          wrong, found);
    cb_bool_bvh_clear(&t);
    /* Degenerate inputs. */
    CHECK(cb_bool_bvh_init(&t, boxes, 0, &err) == CB_OK &&
              cb_bool_bvh_query_box(out, N, &t, &boxes[0], 1) == 0,
          "empty tree");
    cb_bool_bvh_clear(&t);
    boxes[5].lo[1] = NAN;
    CHECK(cb_bool_bvh_init(&t, boxes, N, &err) == CB_ERR_INVALID && strstr(err.msg, "box 5"),
          "NaN box: %s", err.msg);
    free(boxes);
    free(out);
}

/* Two posed birds: the BVH pairs equal the pairs of overlapping boxes found by brute force. */
static void test_face_pairs(void)
{
    cb_hummingbird_params p, q;
    cb_hummingbird_params_default(&p);
    cb_hummingbird_params_default(&q);
    q.axis[0] = 0.3;
    q.axis[1] = 1;
    q.axis[2] = 0.2;
    q.angle_deg = 35;
    q.translate[0] = 0.9;
    q.translate[1] = 0.4;
    q.translate[2] = 0.25;
    cb_topo_body *a = bird(&p), *b = bird(&q);
    if (!a || !b) {
        cb_topo_body_free(a);
        cb_topo_body_free(b);
        return;
    }
    cb_error err;
    int *pairs = NULL, n = 0;
    double tol = 1e-6;
    CHECK(cb_bool_face_pairs(&pairs, &n, a, b, tol, &err) == CB_OK, "%s", err.msg);
    cb_aabb *ba = malloc(a->n_faces * sizeof *ba), *bb = malloc(b->n_faces * sizeof *bb);
    CHECK(cb_bool_face_boxes(ba, a, a->tol, &err) == CB_OK, "%s", err.msg);
    CHECK(cb_bool_face_boxes(bb, b, b->tol, &err) == CB_OK, "%s", err.msg);
    int m = 0, same = 1;
    for (int i = 0; i < a->n_faces; i++)
        for (int j = 0; j < b->n_faces; j++)
            if (cb_aabb_overlap(&ba[i], &bb[j], tol)) {
                same &= m < n && pairs[2 * m] == i && pairs[2 * m + 1] == j;
                m++;
            }
    printf("hummingbird pairs: %d of %d overlap\n", n, a->n_faces * b->n_faces);
    CHECK(same && m == n && n > 50 && n < a->n_faces * b->n_faces / 4,
          "face pairs: %d from the BVH, %d by brute force", n, m);
    free(pairs);
    free(ba);
    free(bb);
    cb_topo_body_free(a);
    cb_topo_body_free(b);
}

/* ---------------------------------------------------------------- primitives --------------- */

typedef enum { P_BOX, P_SPHERE, P_CYLINDER, P_CONE, P_TORUS, P_ELLIPSOID, P_COUNT } prim_kind;
static const char *prim_name[P_COUNT] = {"box", "sphere", "cylinder", "cone", "torus",
                                         "ellipsoid"};

static cb_topo_body *prim(prim_kind k, int as_nurbs)
{
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st;
    static const double lo[3] = {-1, -2, -0.5}, hi[3] = {2, 1, 1.5};
    cb_frame f;
    static const double o[3] = {0.1, -0.2, 0.05}, z[3] = {0.2, 0.1, 1}, x[3] = {1, -0.3, 0};
    cb_frame_make(&f, o, z, x, NULL);
    switch (k) {
    case P_BOX:
        st = cb_prim_box(&b, &f, lo, hi, as_nurbs, 0, &err);
        break;
    case P_SPHERE:
        st = cb_prim_sphere(&b, &f, 1.5, as_nurbs, 0, &err);
        break;
    case P_CYLINDER:
        st = cb_prim_cylinder(&b, &f, 1.0, 2.0, as_nurbs, 0, &err);
        break;
    case P_CONE:
        st = cb_prim_cone(&b, &f, 0.5, 1.5, 2.0, as_nurbs, 0, &err);
        break;
    case P_TORUS:
        st = cb_prim_torus(&b, &f, 2.0, 0.6, as_nurbs, 0, &err);
        break;
    default:
        st = cb_prim_ellipsoid(&b, &f, 1.5, 1.0, 0.7, as_nurbs, 0, &err);
        break;
    }
    CHECK(st == CB_OK, "%s: %s", prim_name[k], err.msg);
    return b;
}

/* A lower bound on the distance from p to the primitive's boundary, signed: > 0 outside. The
 * frame is that of prim(). */
static double prim_side(prim_kind k, const double pw[3])
{
    cb_frame f;
    static const double o[3] = {0.1, -0.2, 0.05}, z[3] = {0.2, 0.1, 1}, x[3] = {1, -0.3, 0};
    cb_frame_make(&f, o, z, x, NULL);
    double p[3];
    cb_frame_to_local(p, &f, pw);
    double rho = hypot(p[0], p[1]);
    switch (k) {
    case P_BOX: {
        static const double lo[3] = {-1, -2, -0.5}, hi[3] = {2, 1, 1.5};
        double s = -HUGE_VAL;
        for (int i = 0; i < 3; i++)
            s = fmax(s, fmax(lo[i] - p[i], p[i] - hi[i]));
        return s;
    }
    case P_SPHERE:
        return cb_vec3_norm(p) - 1.5;
    case P_CYLINDER:
        return fmax(rho - 1, fmax(-p[2], p[2] - 2));
    case P_CONE: /* the slant distance shrinks by cos of the half angle, atan(0.5) */
        return fmax((rho - (0.5 + 0.5 * p[2])) * 0.894427190999916, fmax(-p[2], p[2] - 2));
    case P_TORUS:
        return hypot(rho - 2, p[2]) - 0.6;
    default: { /* scaled to the unit sphere; distances shrink by at most the least semi-axis */
        double x = p[0] / 1.5, y = p[1], zz = p[2] / 0.7;
        return 0.7 * (sqrt(x * x + y * y + zz * zz) - 1);
    }
    }
}

static void test_prims(void)
{
    check_rng rng = {17};
    for (int k = 0; k < P_COUNT; k++)
        for (int nurbs = 0; nurbs < 2; nurbs++) {
            cb_topo_body *b = prim((prim_kind)k, nurbs);
            if (!b)
                continue;
            cb_bool_solid *s;
            cb_error err;
            double tol = 1e-7;
            if (cb_bool_solid_new(&s, b, tol, &err)) {
                CHECK(0, "%s: %s", prim_name[k], err.msg);
                cb_topo_body_free(b);
                continue;
            }
            int wrong = 0, failed = 0, in = 0, n = 0;
            for (int t = 0; t < 300; t++) {
                double p[3];
                for (int i = 0; i < 3; i++)
                    p[i] = check_rng_uniform(&rng, -3, 3);
                double side = prim_side((prim_kind)k, p);
                if (fabs(side) < 1e-5)
                    continue;
                cb_bool_where w;
                if (cb_bool_solid_classify(&w, s, p, &err)) {
                    if (failed++ < 3)
                        fprintf(stderr, "%s: %s\n", prim_name[k], err.msg);
                    continue;
                }
                n++;
                in += w == CB_BOOL_IN;
                if (w != (side < 0 ? CB_BOOL_IN : CB_BOOL_OUT) && wrong++ < 3)
                    fprintf(stderr, "%s%s: (%g %g %g) side %g got %d\n", prim_name[k],
                            nurbs ? " (nurbs)" : "", p[0], p[1], p[2], side, w);
            }
            CHECK(wrong == 0 && failed == 0 && in > 5 && n > 250,
                  "%s%s: %d wrong, %d failed, %d in of %d", prim_name[k], nurbs ? " (nurbs)" : "",
                  wrong, failed, in, n);
            cb_bool_solid_free(s);
            cb_topo_body_free(b);
        }
}

/* ---------------------------------------------------------------- void --------------------- */

/* Appends the analytic sphere `in` to `out` as a void shell of out's solid, its face turned
 * to face into the cavity. */
static void add_void(cb_topo_body *out, const cb_topo_body *in)
{
    int ov = out->n_vertices, oe = out->n_edges, oc = out->n_coedges, ol = out->n_loops,
        of = out->n_faces, os = out->n_shells, ocv = out->n_curves, opc = out->n_pcurves,
        osf = out->n_surfaces;
    for (int k = 0; k < in->n_vertices; k++)
        out->vertices[cb_topo_body_add_vertex(out)] = in->vertices[k];
    for (int k = 0; k < in->n_edges; k++) {
        cb_topo_edge e = in->edges[k];
        e.curve += ocv;
        e.v[0] += ov;
        e.v[1] += ov;
        out->edges[cb_topo_body_add_edge(out)] = e;
    }
    for (int k = 0; k < in->n_coedges; k++) {
        cb_topo_coedge c = in->coedges[k];
        c.edge += oe;
        c.pcurve += opc;
        c.loop += ol;
        out->coedges[cb_topo_body_add_coedge(out)] = c;
    }
    for (int k = 0; k < in->n_loops; k++) {
        cb_topo_loop l = in->loops[k];
        l.first += oc;
        l.face += of;
        out->loops[cb_topo_body_add_loop(out)] = l;
    }
    for (int k = 0; k < in->n_faces; k++) {
        cb_topo_face f = in->faces[k];
        f.surface += osf;
        f.first += ol;
        f.shell += os;
        f.same_sense = !f.same_sense;
        out->faces[cb_topo_body_add_face(out)] = f;
    }
    for (int k = 0; k < in->n_shells; k++) {
        cb_topo_shell s = in->shells[k];
        s.first += of;
        s.solid = 0;
        out->shells[cb_topo_body_add_shell(out)] = s;
    }
    out->solids[0].count += in->n_shells;
    /* Lines, circles and analytic surfaces: plain values, no B-spline storage to share. */
    for (int k = 0; k < in->n_curves; k++) {
        int c = cb_topo_body_add_curve(out);
        out->curves[c].kind = in->curves[k].kind;
        out->curves[c].frame = in->curves[k].frame;
        out->curves[c].r1 = in->curves[k].r1;
        out->curves[c].r2 = in->curves[k].r2;
    }
    for (int k = 0; k < in->n_pcurves; k++) {
        int c = cb_topo_body_add_pcurve(out);
        out->pcurves[c].kind = in->pcurves[k].kind;
        out->pcurves[c].frame = in->pcurves[k].frame;
        out->pcurves[c].r1 = in->pcurves[k].r1;
        out->pcurves[c].r2 = in->pcurves[k].r2;
    }
    for (int k = 0; k < in->n_surfaces; k++) {
        int s = cb_topo_body_add_surface(out);
        out->surfaces[s].kind = in->surfaces[k].kind;
        out->surfaces[s].analytic = in->surfaces[k].analytic;
    }
}

static void test_void(void)
{
    cb_topo_body *outer = NULL, *inner = NULL;
    cb_error err;
    CHECK(cb_prim_sphere(&outer, NULL, 2.0, 0, 0, &err) == CB_OK, "%s", err.msg);
    CHECK(cb_prim_sphere(&inner, NULL, 1.0, 0, 0, &err) == CB_OK, "%s", err.msg);
    if (!outer || !inner) {
        cb_topo_body_free(outer);
        cb_topo_body_free(inner);
        return;
    }
    int plain = 1;
    for (int k = 0; k < inner->n_curves; k++)
        plain &= inner->curves[k].kind != CB_CURVE_NURBS;
    for (int k = 0; k < inner->n_pcurves; k++)
        plain &= inner->pcurves[k].kind != CB_CURVE_NURBS;
    CHECK(plain, "sphere: B-spline curves, the void helper copies plain curves only");
    add_void(outer, inner);
    CHECK(cb_topo_body_index(outer, &err) == CB_OK, "%s", err.msg);
    cb_bool_solid *s;
    if (cb_bool_solid_new(&s, outer, 1e-8, &err)) {
        CHECK(0, "void: %s", err.msg);
    } else {
        check_rng rng = {23};
        int wrong = 0, failed = 0;
        for (int t = 0; t < 200; t++) {
            double d[3], r = check_rng_uniform(&rng, 0, 2.6);
            for (int i = 0; i < 3; i++)
                d[i] = check_rng_uniform(&rng, -1, 1);
            cb_vec3_normalize(d);
            if (fabs(r - 1) < 1e-4 || fabs(r - 2) < 1e-4)
                continue;
            double p[3] = {r * d[0], r * d[1], r * d[2]};
            cb_bool_where w, want = r > 1 && r < 2 ? CB_BOOL_IN : CB_BOOL_OUT;
            if (cb_bool_solid_classify(&w, s, p, &err))
                failed++;
            else
                wrong += w != want;
        }
        double on[3] = {0.6, 0.8, 0};
        cb_bool_where w;
        CHECK(cb_bool_solid_classify(&w, s, on, &err) == CB_OK && w == CB_BOOL_ON,
              "on the void's face: %d", w);
        CHECK(wrong == 0 && failed == 0, "void: %d wrong, %d failed", wrong, failed);
        cb_bool_solid_free(s);
    }
    cb_topo_body_free(outer);
    cb_topo_body_free(inner);
}

/* ---------------------------------------------------------------- models ------------------- */

/* Points on the faces are ON; pushed out along the face normal by 100 tol they are OUT, and
 * pushed in IN, where no other face comes within that distance (a thin wall, a concave
 * edge). */
static void on_and_beside(const char *name, const cb_topo_body *b, double tol, int n_points)
{
    cb_bool_solid *s;
    cb_error err;
    if (cb_bool_solid_new(&s, b, tol, &err)) {
        CHECK(0, "%s: %s", name, err.msg);
        return;
    }
    check_rng rng = {41};
    int on_wrong = 0, side_wrong = 0, failed = 0, sides = 0, ons = 0;
    for (int t = 0; t < n_points; t++) {
        int fi = check_rng_int(&rng, 0, b->n_faces - 1);
        const cb_face *f = cb_bool_solid_face(s, fi);
        double uv[2];
        int found = 0;
        for (int a = 0; a < 50 && !found; a++) {
            for (int i = 0; i < 2; i++)
                uv[i] = check_rng_uniform(&rng, f->uv_box[2 * i], f->uv_box[2 * i + 1]);
            found = cb_face_classify_uv(f, uv[0], uv[1], tol) == CB_FACE_IN;
        }
        if (!found)
            continue;
        double p[3], n[3];
        cb_topo_inverter_eval(p, &f->inv, uv[0], uv[1]);
        if (!(cb_face_normal(n, f, uv[0], uv[1]) > 0))
            continue;
        cb_bool_where w;
        ons++;
        if (cb_bool_solid_classify(&w, s, p, &err) || w != CB_BOOL_ON)
            on_wrong++;
        for (int sd = -1; sd <= 1; sd += 2) {
            double q[3], h = 100 * tol;
            for (int i = 0; i < 3; i++)
                q[i] = p[i] + sd * h * n[i];
            int thin = 0;
            for (int g = 0; g < b->n_faces && !thin; g++)
                if (g != fi)
                    thin = cb_face_distance(NULL, cb_bool_solid_face(s, g), q) < 1.5 * h;
            if (thin)
                continue;
            sides++;
            if (cb_bool_solid_classify(&w, s, q, &err)) {
                if (failed++ < 3)
                    fprintf(stderr, "%s: %s\n", name, err.msg);
                continue;
            }
            if (w != (sd > 0 ? CB_BOOL_OUT : CB_BOOL_IN) && side_wrong++ < 3)
                fprintf(stderr, "%s face %d (%g, %g) side %d: got %d\n", name, fi, uv[0], uv[1],
                        sd, w);
        }
    }
    printf("%s: %d face points, %d pushed points classified\n", name, ons, sides);
    CHECK(on_wrong == 0 && ons > n_points / 2, "%s: %d of %d face points not ON", name, on_wrong,
          ons);
    CHECK(side_wrong == 0 && failed == 0 && sides > ons,
          "%s: %d of %d pushed points wrong, %d failed", name, side_wrong, sides, failed);
    cb_bool_solid_free(s);
}

/* The fraction of uniform random points of the box found IN estimates volume / box volume;
 * the binomial standard deviation bounds the difference. */
static void in_fraction(const char *name, const cb_topo_body *b, double tol, double volume_mm3,
                        int n)
{
    cb_bool_solid *s;
    cb_error err;
    if (cb_bool_solid_new(&s, b, tol, &err)) {
        CHECK(0, "%s: %s", name, err.msg);
        return;
    }
    cb_aabb box;
    cb_bool_solid_box(&box, s);
    check_rng rng = {97};
    int in = 0, failed = 0;
    for (int t = 0; t < n; t++) {
        double p[3];
        for (int i = 0; i < 3; i++)
            p[i] = check_rng_uniform(&rng, box.lo[i], box.hi[i]);
        cb_bool_where w;
        if (cb_bool_solid_classify(&w, s, p, &err)) {
            if (failed++ < 3)
                fprintf(stderr, "%s: %s\n", name, err.msg);
            continue;
        }
        in += w == CB_BOOL_IN;
    }
    double frac = (double)in / n, want = volume_mm3 / pow(b->length_unit_mm, 3) /
                                         cb_aabb_volume(&box);
    double sigma = sqrt(want * (1 - want) / n);
    printf("%s: %d of %d random points in, fraction %.4f, volume ratio %.4f (sigma %.4f)\n", name,
           in, n, frac, want, sigma);
    CHECK(failed == 0 && fabs(frac - want) < 4 * sigma + 1.0 / n,
          "%s: fraction in %g, volume ratio %g, sigma %g, %d failed", name, frac, want, sigma,
          failed);
    cb_bool_solid_free(s);
}

/* The hummingbird's volume by the divergence theorem: its faces are untrimmed polynomial
 * bicubic patches, so 5-point Gauss-Legendre per knot span integrates S . (S_u x S_v) (degree
 * 8 per parameter) exactly to round-off. */
static double bird_volume(const cb_topo_body *b)
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

static void test_models(void)
{
    static const char *files[] = {"ujoint_fork.step", "ujoint_cross.step", "linkrods.step",
                                  "trj5_k1-al-214.stp"};
    for (int k = 0; k < 4; k++) {
        cb_topo_body *b = load(files[k]);
        if (!b)
            continue;
        double tol = b->tol;
        on_and_beside(files[k], b, tol, 60);
        if (k == 0)
            in_fraction(files[k], b, tol, 81046.104, 10000);
        if (k == 1)
            in_fraction(files[k], b, tol, 95097.336, 10000);
        cb_topo_body_free(b);
    }
    cb_hummingbird_params p;
    cb_hummingbird_params_default(&p);
    cb_topo_body *b = bird(&p);
    if (b) {
        on_and_beside("hummingbird", b, 100 * b->tol, 60);
        in_fraction("hummingbird", b, 100 * b->tol, bird_volume(b) * pow(b->length_unit_mm, 3),
                    3000);
        cb_topo_body_free(b);
    }
}

/* ---------------------------------------------------------------- bad input ---------------- */

static void test_bad_input(void)
{
    cb_topo_body *b = prim(P_CYLINDER, 0);
    if (!b)
        return;
    cb_bool_solid *s = NULL;
    cb_error err;
    cb_bool_where w;
    CHECK(cb_bool_solid_new(&s, b, 0, &err) == CB_ERR_INVALID && !s &&
              strstr(err.msg, "tolerance"),
          "zero tolerance: %s", err.msg);
    double nan_point[3] = {0, NAN, 0};
    CHECK(cb_bool_point_in_solid(&w, b, nan_point, 1e-7, &err) == CB_ERR_INVALID,
          "NaN point");
    int c = b->loops[b->faces[0].first].first, keep = b->coedges[c].pcurve;
    b->coedges[c].pcurve = -1;
    double o[3] = {0, 0, 0};
    CHECK(cb_bool_point_in_solid(&w, b, o, 1e-7, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "pcurve"),
          "missing pcurve: %s", err.msg);
    b->coedges[c].pcurve = keep;
    cb_topo_body_free(b);
}

int main(void)
{
    test_bvh();
    test_face_pairs();
    test_prims();
    test_void();
    test_models();
    test_bad_input();
    return check_report("test_bool_classify");
}
