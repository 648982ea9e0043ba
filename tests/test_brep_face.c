/* Trimmed-face queries (brep/face.h): the inside/outside/on test in (u, v) against exact
 * membership on primitive solids, seams, poles and holes, loop orientation and the divergence
 * volume of the shipped models; boxes against dense samples; rays on analytic faces against
 * the same faces as rational B-splines; distances against closed forms; bad input. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "boolean/bool.h"
#include "brep/face.h"
#include "brep/prim.h"
#include "check.h"
#include "io/step.h"
#include "models/models.h"

static const double PI = 3.14159265358979323846;

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
    cb_status st = cb_step_read(&b, path, &err);
    CHECK(st == CB_OK, "%s: %s", name, err.msg);
    return b;
}

static cb_topo_body *bird(void)
{
    cb_hummingbird_params p;
    cb_hummingbird_params_default(&p);
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = cb_model_hummingbird(&b, &p, &err);
    if (!st)
        st = cb_topo_compute_pcurves(b, 10 * b->tol, &err);
    CHECK(st == CB_OK, "hummingbird: %s", err.msg);
    return b;
}

static double body_tol(const cb_topo_body *b) { return b->tol > 0 ? b->tol : 1e-7; }

/* ---------------------------------------------------------------- primitives --------------- */

typedef enum { P_BOX, P_SPHERE, P_CYLINDER, P_CONE, P_TORUS, P_ELLIPSOID, P_COUNT } prim_kind;
static const char *prim_name[P_COUNT] = {"box", "sphere", "cylinder", "cone", "torus",
                                         "ellipsoid"};

static cb_topo_body *prim(prim_kind k, int as_nurbs)
{
    cb_topo_body *b = NULL;
    cb_error err;
    cb_status st = CB_OK;
    static const double lo[3] = {-1, -2, -0.5}, hi[3] = {2, 1, 1.5};
    switch (k) {
    case P_BOX:
        st = cb_prim_box(&b, NULL, lo, hi, as_nurbs, 0, &err);
        break;
    case P_SPHERE:
        st = cb_prim_sphere(&b, NULL, 1.5, as_nurbs, 0, &err);
        break;
    case P_CYLINDER:
        st = cb_prim_cylinder(&b, NULL, 1.0, 2.0, as_nurbs, 0, &err);
        break;
    case P_CONE:
        st = cb_prim_cone(&b, NULL, 0.5, 1.5, 2.0, as_nurbs, 0, &err);
        break;
    case P_TORUS:
        st = cb_prim_torus(&b, NULL, 2.0, 0.6, as_nurbs, 0, &err);
        break;
    default:
        st = cb_prim_ellipsoid(&b, NULL, 1.5, 1.0, 0.7, as_nurbs, 0, &err);
        break;
    }
    CHECK(st == CB_OK, "%s: %s", prim_name[k], err.msg);
    return b;
}

/* > 0 outside the primitive, < 0 inside, 0 on its boundary (not a distance except for the
 * sphere). */
static double prim_side(prim_kind k, const double p[3])
{
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
    case P_CONE:
        return fmax(rho - (0.5 + 0.5 * p[2]), fmax(-p[2], p[2] - 2));
    case P_TORUS:
        return hypot(rho - 2, p[2]) - 0.6;
    default: {
        double x = p[0] / 1.5, y = p[1], z = p[2] / 0.7;
        return sqrt(x * x + y * y + z * z) - 1;
    }
    }
}

static double boundary_distance(const cb_face *f, const double p[3])
{
    return cb_face_boundary_distance(f, p);
}

/* Random (u, v) in the face's box, 10% beyond it where the surface is not periodic (within
 * the surface's domain). */
static void random_uv(double uv[2], const cb_face *f, check_rng *rng)
{
    for (int i = 0; i < 2; i++) {
        double lo = f->uv_box[2 * i], hi = f->uv_box[2 * i + 1], m = 0;
        if (f->inv.period[i] <= 0)
            m = 0.1 * (hi - lo);
        uv[i] = check_rng_uniform(rng, fmax(lo - m, f->inv.box[2 * i]),
                                  fmin(hi + m, f->inv.box[2 * i + 1]));
    }
}

/* The face of a primitive holds S(u, v) iff the point is on the solid's boundary (and, for
 * the torus, on the face's half). */
static void test_prim_classify(void)
{
    check_rng rng = {11};
    for (int k = 0; k < P_COUNT; k++)
        for (int nurbs = 0; nurbs < 2; nurbs++) {
            cb_topo_body *b = prim((prim_kind)k, nurbs);
            if (!b)
                continue;
            double tol = body_tol(b), size = 3;
            int wrong = 0, tried = 0, in = 0, seam_wrong = 0;
            for (int fi = 0; fi < b->n_faces; fi++) {
                cb_face f;
                cb_error err;
                if (cb_face_init(&f, b, fi, tol, &err)) {
                    CHECK(0, "%s face %d: %s", prim_name[k], fi, err.msg);
                    continue;
                }
                double mid[3];
                cb_topo_inverter_eval(mid, &f.inv, 0.5 * (f.uv_box[0] + f.uv_box[1]),
                                      0.5 * (f.uv_box[2] + f.uv_box[3]));
                for (int t = 0; t < 400; t++) {
                    double uv[2], p[3];
                    random_uv(uv, &f, &rng);
                    cb_topo_inverter_eval(p, &f.inv, uv[0], uv[1]);
                    if (boundary_distance(&f, p) < 1e-6 * size)
                        continue;
                    int truth = prim_side((prim_kind)k, p) < 1e-7 * size;
                    if (k == P_TORUS)
                        truth = p[1] * mid[1] > 0;
                    cb_face_where w = cb_face_classify_uv(&f, uv[0], uv[1], tol);
                    tried++;
                    in += w == CB_FACE_IN;
                    if ((w == CB_FACE_IN) != truth || w == CB_FACE_ON) {
                        if (wrong++ < 3)
                            fprintf(stderr, "%s%s face %d (%g, %g): got %d want %d\n",
                                    prim_name[k], nurbs ? " (nurbs)" : "", fi, uv[0], uv[1], w,
                                    truth);
                    }
                    /* Any lift of a periodic parameter gives the same answer. */
                    for (int i = 0; i < 2; i++)
                        if (f.inv.period[i] > 0) {
                            double w2[2] = {uv[0], uv[1]};
                            w2[i] += (t % 2 ? -3 : 2) * f.inv.period[i];
                            seam_wrong += cb_face_classify_uv(&f, w2[0], w2[1], tol) != w;
                        }
                }
                /* Points just beside a seam are inside, never on it. */
                for (int i = 0; i < 2; i++)
                    if (f.inv.period[i] > 0 && (k == P_SPHERE || k == P_CYLINDER) && fi == 0) {
                        double uv[2] = {0, 0.3};
                        uv[i] = f.inv.box[2 * i] + 1e-12;
                        CHECK(cb_face_classify_uv(&f, uv[0], uv[1], tol) == CB_FACE_IN,
                              "%s: beside the seam", prim_name[k]);
                        uv[i] = f.inv.box[2 * i] + f.inv.period[i] - 1e-12;
                        CHECK(cb_face_classify_uv(&f, uv[0], uv[1], tol) == CB_FACE_IN,
                              "%s: beside the seam, other side", prim_name[k]);
                    }
                cb_face_clear(&f);
            }
            CHECK(wrong == 0 && tried > 300 && in > 30, "%s%s: %d of %d wrong (%d in)",
                  prim_name[k], nurbs ? " (nurbs)" : "", wrong, tried, in);
            CHECK(seam_wrong == 0, "%s%s: %d lifts disagree", prim_name[k],
                  nurbs ? " (nurbs)" : "", seam_wrong);
            cb_topo_body_free(b);
        }
}

/* Sphere poles: the north pole and a point a hair from it are inside the sphere's face. */
static void test_poles(void)
{
    cb_topo_body *b = prim(P_SPHERE, 0);
    if (!b)
        return;
    cb_face f;
    cb_error err;
    CHECK(cb_face_init(&f, b, 0, b->tol, &err) == CB_OK, "%s", err.msg);
    for (int i = 0; i < 16; i++) {
        double u = 2 * PI * i / 16 + 0.1;
        CHECK(cb_face_classify_uv(&f, u, PI / 2 - 1e-9, b->tol) == CB_FACE_IN, "near pole u %g",
              u);
        CHECK(cb_face_classify_uv(&f, u, -PI / 2 + 1e-9, b->tol) == CB_FACE_IN,
              "near south pole u %g", u);
    }
    cb_face_clear(&f);
    cb_topo_body_free(b);
}

/* ---------------------------------------------------------------- models ------------------- */

/* Every point of a pcurve is ON; points beside it by 50 tol in 3D are IN on the face's side
 * (left of the coedge in (u, v) for same_sense = 1) and OUT on the other, unless another
 * boundary edge is as near. */
static void loop_sides(const char *name, const cb_topo_body *b, double tol)
{
    int on_wrong = 0, side_wrong = 0, sides = 0, ons = 0;
    for (int fi = 0; fi < b->n_faces; fi++) {
        cb_face f;
        cb_error err;
        if (cb_face_init(&f, b, fi, tol, &err)) {
            CHECK(0, "%s face %d: %s", name, fi, err.msg);
            continue;
        }
        const cb_topo_face *fc = &b->faces[fi];
        for (int s = 0; s < f.n_segs; s++) {
            const cb_face_seg *sg = &f.segs[s];
            if (sg->coedge < 0)
                continue;
            int e = b->coedges[sg->coedge].edge, boundary = 0;
            for (int k = 0; k < f.n_edges; k++)
                boundary |= f.edges[k].edge == e && f.edges[k].boundary;
            if (!boundary)
                continue;
            const cb_topo_curve *pc = &b->pcurves[b->coedges[sg->coedge].pcurve];
            double sm = 0.5 * (sg->s0 + sg->s1), h = 1e-6 * (sg->s1 - sg->s0);
            double w[3], w1[3], w2[3], p[3];
            cb_topo_pcurve_eval(w, pc, sm);
            cb_topo_pcurve_eval(w1, pc, sm - h);
            cb_topo_pcurve_eval(w2, pc, sm + h);
            double uv[2] = {w[0] + sg->shift[0], w[1] + sg->shift[1]};
            ons++;
            double etol = 2 * fmax(tol, b->edges[e].tol);
            if (cb_face_classify_uv(&f, uv[0], uv[1], etol) != CB_FACE_ON) {
                cb_topo_inverter_eval(p, &f.inv, uv[0], uv[1]);
                if (on_wrong++ < 3)
                    fprintf(stderr, "%s face %d coedge %d: pcurve point %g from the boundary"
                                    " (tol %g)\n",
                            name, fi, sg->coedge, boundary_distance(&f, p), etol);
            }
            double t[2] = {w2[0] - w1[0], w2[1] - w1[1]}, d[6][3];
            double left[2] = {-t[1], t[0]};
            cb_topo_inverter_eval_derivs(d, &f.inv, uv[0], uv[1]);
            double j3[3];
            for (int i = 0; i < 3; i++)
                j3[i] = d[1][i] * left[0] + d[2][i] * left[1];
            double jl = cb_vec3_norm(j3);
            if (!(jl > 0))
                continue;
            double step = 50 * tol / jl;
            for (int sd = -1; sd <= 1; sd += 2) {
                double q[2] = {uv[0] + sd * step * left[0], uv[1] + sd * step * left[1]};
                cb_topo_inverter_eval(p, &f.inv, q[0], q[1]);
                if (boundary_distance(&f, p) < 25 * tol)
                    continue;
                int want = (sd > 0) == (fc->same_sense != 0);
                cb_face_where got = cb_face_classify_uv(&f, q[0], q[1], tol);
                sides++;
                if ((got == CB_FACE_IN) != want || got == CB_FACE_ON) {
                    if (side_wrong++ < 3)
                        fprintf(stderr, "%s face %d coedge %d side %d: got %d\n", name, fi,
                                sg->coedge, sd, got);
                }
            }
        }
        cb_face_clear(&f);
    }
    CHECK(on_wrong == 0, "%s: %d of %d pcurve points not ON", name, on_wrong, ons);
    CHECK(side_wrong == 0 && sides > 20, "%s: %d of %d side points wrong", name, side_wrong,
          sides);
}

/* Enclosed volume by the divergence theorem over an n x n midpoint grid of each face's
 * (u, v) box, each point weighted by cb_face_classify_uv (ON counts half). */
static double grid_volume(const cb_topo_body *b, double tol, int n)
{
    double vol = 0;
    for (int fi = 0; fi < b->n_faces; fi++) {
        cb_face f;
        cb_error err;
        if (cb_face_init(&f, b, fi, tol, &err)) {
            CHECK(0, "face %d: %s", fi, err.msg);
            continue;
        }
        double du = (f.uv_box[1] - f.uv_box[0]) / n, dv = (f.uv_box[3] - f.uv_box[2]) / n;
        double sum = 0;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double u = f.uv_box[0] + (i + 0.5) * du, v = f.uv_box[2] + (j + 0.5) * dv;
                cb_face_where w = cb_face_classify_uv(&f, u, v, tol);
                if (w == CB_FACE_OUT)
                    continue;
                double d[6][3], nrm[3];
                cb_topo_inverter_eval_derivs(d, &f.inv, u, v);
                cb_vec3_cross(nrm, d[1], d[2]);
                sum += (w == CB_FACE_ON ? 0.5 : 1.0) * cb_vec3_dot(d[0], nrm) / 3;
            }
        vol += (b->faces[fi].same_sense ? 1 : -1) * sum * du * dv;
        cb_face_clear(&f);
    }
    return vol;
}

typedef struct {
    const char *file;
    double volume_mm3; /* SOURCES.md */
} model_ref;

static void test_models(void)
{
    static const model_ref refs[] = {{"ujoint_fork.step", 81046.104},
                                     {"ujoint_cross.step", 95097.336},
                                     {"linkrods.step", 3.847013},
                                     {"trj5_k1-al-214.stp", 7936.1475}};
    for (size_t k = 0; k < sizeof refs / sizeof refs[0]; k++) {
        cb_topo_body *b = load(refs[k].file);
        if (!b)
            continue;
        double tol = body_tol(b), u3 = pow(b->length_unit_mm, 3);
        loop_sides(refs[k].file, b, tol);
        double vol = grid_volume(b, tol, 120) * u3;
        double rel = fabs(vol - refs[k].volume_mm3) / refs[k].volume_mm3;
        printf("%s: grid volume %.6g mm^3, reference %.8g, relative error %.2e\n", refs[k].file,
               vol, refs[k].volume_mm3, rel);
        CHECK(rel < 1e-2, "%s: volume %g, reference %g", refs[k].file, vol, refs[k].volume_mm3);
        cb_topo_body_free(b);
    }
    cb_topo_body *b = bird();
    if (b) {
        loop_sides("hummingbird", b, b->tol);
        cb_topo_body_free(b);
    }
}

/* ---------------------------------------------------------------- boxes -------------------- */

static void boxes_hold(const char *name, const cb_topo_body *b, double tol, int n)
{
    int outside = 0, samples = 0;
    double worst = 0;
    for (int fi = 0; fi < b->n_faces; fi++) {
        cb_face f;
        cb_error err;
        if (cb_face_init(&f, b, fi, tol, &err)) {
            CHECK(0, "%s face %d: %s", name, fi, err.msg);
            continue;
        }
        cb_aabb box;
        cb_face_box(&box, &f);
        double scale = 0;
        for (int i = 0; i < 3; i++)
            scale = fmax(scale, fmax(fabs(box.lo[i]), fabs(box.hi[i])));
        for (int i = 0; i <= n; i++)
            for (int j = 0; j <= n; j++) {
                double u = f.uv_box[0] + (f.uv_box[1] - f.uv_box[0]) * i / n;
                double v = f.uv_box[2] + (f.uv_box[3] - f.uv_box[2]) * j / n, p[3];
                if (cb_face_classify_uv(&f, u, v, tol) == CB_FACE_OUT)
                    continue;
                cb_topo_inverter_eval(p, &f.inv, u, v);
                samples++;
                double out = 0;
                for (int c = 0; c < 3; c++)
                    out = fmax(out, fmax(box.lo[c] - p[c], p[c] - box.hi[c]));
                worst = fmax(worst, out / scale);
                outside += out > 1e-13 * scale;
            }
        cb_face_clear(&f);
    }
    CHECK(outside == 0 && samples > 100 * b->n_faces, "%s: %d of %d samples outside (worst %g)",
          name, outside, samples, worst);
}

static void test_boxes(void)
{
    static const char *files[] = {"ujoint_fork.step", "ujoint_cross.step", "linkrods.step",
                                  "trj5_k1-al-214.stp"};
    for (int k = 0; k < 4; k++) {
        cb_topo_body *b = load(files[k]);
        if (b) {
            boxes_hold(files[k], b, body_tol(b), 24);
            cb_topo_body_free(b);
        }
    }
    cb_topo_body *b = bird();
    if (b) {
        boxes_hold("hummingbird", b, b->tol, 24);
        cb_topo_body_free(b);
    }
    for (int k = 0; k < P_COUNT; k++)
        for (int nurbs = 0; nurbs < 2; nurbs++) {
            b = prim((prim_kind)k, nurbs);
            if (!b)
                continue;
            boxes_hold(prim_name[k], b, b->tol, 40);
            /* Tight where exact: the box's faces are their own boxes; the sphere's face box
             * is the cube around it. */
            if (k == P_BOX || k == P_SPHERE) {
                cb_aabb all = {{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
                for (int fi = 0; fi < b->n_faces; fi++) {
                    cb_face f;
                    cb_error err;
                    if (cb_face_init(&f, b, fi, b->tol, &err))
                        continue;
                    for (int i = 0; i < 3; i++) {
                        all.lo[i] = fmin(all.lo[i], f.box.lo[i]);
                        all.hi[i] = fmax(all.hi[i], f.box.hi[i]);
                    }
                    cb_face_clear(&f);
                }
                double want_lo[3] = {-1, -2, -0.5}, want_hi[3] = {2, 1, 1.5}, dev = 0;
                if (k == P_SPHERE)
                    for (int i = 0; i < 3; i++) {
                        want_lo[i] = -1.5;
                        want_hi[i] = 1.5;
                    }
                for (int i = 0; i < 3; i++)
                    dev = fmax(dev, fmax(fabs(all.lo[i] - want_lo[i]),
                                         fabs(all.hi[i] - want_hi[i])));
                CHECK(dev < 1e-9, "%s%s: face boxes off the exact box by %g", prim_name[k],
                      nurbs ? " (nurbs)" : "", dev);
            }
            cb_topo_body_free(b);
        }
}

/* ---------------------------------------------------------------- rays --------------------- */

/* All hits of a ray with the faces of a body; returns the count, or -1 when one is not a
 * transversal crossing. */
static int body_hits(double *t, int max, cb_face *faces, int nf, const double o[3],
                     const double d[3], double tol, double *on_surface)
{
    int n = 0;
    for (int fi = 0; fi < nf; fi++) {
        cb_face_hit h[16];
        int m = cb_face_ray(h, 16, &faces[fi], o, d, 0, 100, tol, 1e-3);
        for (int k = 0; k < m && k < 16; k++) {
            if (h[k].kind != CB_FACE_HIT_CROSS)
                return -1;
            double p[3], q[3];
            cb_topo_inverter_eval(p, &faces[fi].inv, h[k].u, h[k].v);
            for (int i = 0; i < 3; i++)
                q[i] = o[i] + h[k].t * d[i];
            *on_surface = fmax(*on_surface, cb_vec3_dist(p, q));
            if (n < max)
                t[n++] = h[k].t;
        }
    }
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && t[j] < t[j - 1]; j--) {
            double x = t[j];
            t[j] = t[j - 1];
            t[j - 1] = x;
        }
    return n;
}

static cb_face *prepare_all(const cb_topo_body *b, double tol)
{
    cb_face *f = calloc((size_t)b->n_faces, sizeof *f);
    for (int k = 0; f && k < b->n_faces; k++) {
        cb_error err;
        CHECK(cb_face_init(&f[k], b, k, tol, &err) == CB_OK, "face %d: %s", k, err.msg);
    }
    return f;
}

static void free_all(cb_face *f, int n)
{
    for (int k = 0; k < n; k++)
        cb_face_clear(&f[k]);
    free(f);
}

static void test_rays(void)
{
    check_rng rng = {29};
    for (int k = 0; k < P_COUNT; k++) {
        cb_topo_body *a = prim((prim_kind)k, 0), *nb = prim((prim_kind)k, 1);
        if (!a || !nb) {
            cb_topo_body_free(a);
            cb_topo_body_free(nb);
            continue;
        }
        cb_face *fa = prepare_all(a, a->tol), *fn = prepare_all(nb, nb->tol);
        int compared = 0, differ = 0, parity_wrong = 0;
        double worst_t = 0, on_a = 0, on_n = 0;
        for (int r = 0; r < 300; r++) {
            double o[3], d[3];
            for (int i = 0; i < 3; i++) {
                o[i] = check_rng_uniform(&rng, -3, 3);
                d[i] = check_rng_uniform(&rng, -1, 1);
            }
            double ta[16], tn[16];
            int na = body_hits(ta, 16, fa, a->n_faces, o, d, 1e-9, &on_a);
            int nn = body_hits(tn, 16, fn, nb->n_faces, o, d, 1e-9, &on_n);
            if (na < 0 || nn < 0)
                continue;
            compared++;
            if (na != nn) {
                if (differ++ < 3)
                    fprintf(stderr, "%s ray %d: %d analytic hits, %d nurbs hits\n", prim_name[k],
                            r, na, nn);
                continue;
            }
            for (int i = 0; i < na; i++)
                worst_t = fmax(worst_t, fabs(ta[i] - tn[i]));
            /* Far past the solid the ray is outside: the parity of the hits is the origin's
             * side. */
            int inside = prim_side((prim_kind)k, o) < 0;
            parity_wrong += (na % 2) != inside;
        }
        CHECK(compared > 200 && differ == 0 && worst_t < 1e-7,
              "%s: %d rays compared, %d differ in count, worst t difference %g", prim_name[k],
              compared, differ, worst_t);
        CHECK(parity_wrong == 0, "%s: %d rays with a wrong parity", prim_name[k], parity_wrong);
        CHECK(on_a < 1e-9 && on_n < 1e-9, "%s: hits off the surface by %g, %g", prim_name[k], on_a,
              on_n);
        free_all(fa, a->n_faces);
        free_all(fn, nb->n_faces);
        cb_topo_body_free(a);
        cb_topo_body_free(nb);
    }
}

/* ---------------------------------------------------------------- distances ---------------- */

static void test_distance(void)
{
    check_rng rng = {5};
    for (int nurbs = 0; nurbs < 2; nurbs++) {
        cb_topo_body *s = prim(P_SPHERE, nurbs), *c = prim(P_CYLINDER, nurbs);
        if (!s || !c) {
            cb_topo_body_free(s);
            cb_topo_body_free(c);
            continue;
        }
        cb_face fs, fc;
        cb_error err;
        CHECK(cb_face_init(&fs, s, 0, s->tol, &err) == CB_OK, "%s", err.msg);
        /* The cylinder's side is face 0. */
        CHECK(cb_face_init(&fc, c, 0, c->tol, &err) == CB_OK, "%s", err.msg);
        double worst_s = 0, worst_c = 0;
        for (int t = 0; t < 300; t++) {
            double p[3];
            for (int i = 0; i < 3; i++)
                p[i] = check_rng_uniform(&rng, -3, 3);
            double ds = cb_face_distance(NULL, &fs, p);
            worst_s = fmax(worst_s, fabs(ds - fabs(cb_vec3_norm(p) - 1.5)));
            double rho = hypot(p[0], p[1]), z = fmin(fmax(p[2], 0), 2);
            double want = hypot(rho - 1, p[2] - z);
            worst_c = fmax(worst_c, fabs(cb_face_distance(NULL, &fc, p) - want));
        }
        CHECK(worst_s < 1e-9 && worst_c < 1e-8, "%s: distance errors sphere %g cylinder side %g",
              nurbs ? "nurbs" : "analytic", worst_s, worst_c);
        cb_face_clear(&fs);
        cb_face_clear(&fc);
        cb_topo_body_free(s);
        cb_topo_body_free(c);
    }
}

/* ---------------------------------------------------------------- bad input ---------------- */

static void test_bad_input(void)
{
    cb_topo_body *b = prim(P_CYLINDER, 0);
    if (!b)
        return;
    cb_face f;
    cb_error err;
    CHECK(cb_face_init(&f, b, b->n_faces, b->tol, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "out of range"),
          "face out of range: %s", err.msg);
    CHECK(cb_face_init(&f, b, -1, b->tol, &err) == CB_ERR_INVALID, "negative face");
    CHECK(cb_face_init(&f, b, 0, 0, &err) == CB_ERR_INVALID && strstr(err.msg, "tolerance"),
          "zero tolerance: %s", err.msg);
    int c = b->loops[b->faces[1].first].first, keep = b->coedges[c].pcurve;
    b->coedges[c].pcurve = -1;
    CHECK(cb_face_init(&f, b, 1, b->tol, &err) == CB_ERR_INVALID && strstr(err.msg, "pcurve"),
          "missing pcurve: %s", err.msg);
    b->coedges[c].pcurve = keep;
    cb_aabb box;
    double uv[4] = {0, NAN, 0, 1};
    CHECK(cb_face_surface_box(&box, &b->surfaces[0], uv, &err) == CB_ERR_INVALID,
          "non-finite rectangle");
    cb_topo_body_free(b);
}

/* Points of body b's boundary edges, 1000 per edge, not classified ON by their faces. */
static int edge_points_not_on(const char *name, const cb_topo_body *b, int *tried)
{
    double tol = body_tol(b);
    int wrong = 0;
    for (int fi = 0; fi < b->n_faces; fi++) {
        cb_face f;
        cb_error err;
        if (cb_face_init(&f, b, fi, tol, &err)) {
            CHECK(0, "%s face %d: %s", name, fi, err.msg);
            continue;
        }
        for (int j = 0; j < f.n_edges; j++) {
            if (!f.edges[j].boundary)
                continue;
            const cb_topo_edge *e = b->edges + f.edges[j].edge;
            for (int i = 0; i <= 1000; i++) {
                double t = e->t0 + (e->t1 - e->t0) * i / 1000, x[3], uv[2];
                cb_topo_curve_eval(x, b->curves + e->curve, t);
                cb_topo_inverter_invert(uv, &f.inv, x, NULL);
                (*tried)++;
                if (cb_face_classify_uv(&f, uv[0], uv[1], tol) != CB_FACE_ON && wrong++ < 3)
                    fprintf(stderr, "%s face %d edge %d t %.9g: not ON (%g from the boundary)\n",
                            name, fi, f.edges[j].edge, t, boundary_distance(&f, x));
            }
        }
        cb_face_clear(&f);
    }
    return wrong;
}

/* Every point of every boundary edge is ON, densely sampled. On a closed B-spline edge (a
 * hole's rim as Open CASCADE writes it: a rational circle starting at its vertex) the points
 * of the last sample interval once came out IN: the edge distance started Newton at the first
 * sample, equal to the last, and stayed clamped at the curve's start. */
static void test_edge_points_on(void)
{
    for (int k = 0; k < P_COUNT; k++)
        for (int nurbs = 0; nurbs < 2; nurbs++) {
            cb_topo_body *b = prim((prim_kind)k, nurbs);
            if (!b)
                continue;
            char name[64];
            snprintf(name, sizeof name, "%s%s", nurbs ? "nurbs " : "", prim_name[k]);
            int tried = 0, wrong = edge_points_not_on(name, b, &tried);
            /* spheres and ellipsoids have no boundary edge */
            CHECK(wrong == 0 && (tried > 0 || k == P_SPHERE || k == P_ELLIPSOID),
                  "%s: %d of %d edge points not ON", name, wrong, tried);
            cb_topo_body_free(b);
        }
    const char *src = getenv("COLIBRI_SOURCE");
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/corpus/holed_plug_0_axis_nurbs_a.step",
             src ? src : ".");
    cb_topo_body *b = NULL;
    cb_error err;
    CHECK(cb_step_read(&b, path, &err) == CB_OK, "%s: %s", path, err.msg);
    if (b) {
        int tried = 0, wrong = edge_points_not_on("holed_plug_0_axis_nurbs_a", b, &tried);
        CHECK(wrong == 0 && tried > 10000, "holed box: %d of %d edge points not ON", wrong,
              tried);
        cb_topo_body_free(b);
    }
}

/* A hole in a cylinder's side face whose pcurves lie a period away from the outer loop's (a
 * file writing angles in (-pi, pi] for the hole and [0, 2 pi] for the loop that starts on the
 * seam): the hole is placed in the outer loop's range (the lift bringing its middle nearest the
 * outer loop's middle). The face: a unit cylinder (seam at angle 0, 0 <= z <= 4) minus a
 * radial drill of radius 0.3 at angle 3.6, z = 2, which leaves a hole round that angle; its
 * pcurves are then moved by -2 pi, to angles about -2.7, nearer the seam at 0 than the seam at
 * 2 pi. Placed by the outer loop's first point (on the seam at 0), as before, the hole stayed
 * a period off in both passes (the Boolean's own pcurves put it at -2.7 too), outside the
 * band: trj6_k1-ec-214's band with a slot was then split into regions whose inner points lay
 * on its seam, and dropped. */
static void test_hole_lift(void)
{
    const double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, c[3] = {0, 0, 2}, ang = 3.6;
    const double mx[3] = {cos(ang), sin(ang), 0};
    cb_frame fa, fb;
    cb_topo_body *A = NULL, *B = NULL, *R = NULL;
    cb_error err;
    cb_status st = cb_frame_make(&fa, o, z, NULL, &err);
    if (!st)
        st = cb_frame_make(&fb, c, mx, NULL, &err);
    if (!st)
        st = cb_prim_cylinder(&A, &fa, 1, 4, 0, 0, &err);
    if (!st)
        st = cb_prim_cylinder(&B, &fb, 0.3, 2, 0, 0, &err);
    if (!st)
        st = cb_bool_run(&R, NULL, CB_BOOL_DIFFERENCE, A, B, NULL, NULL, &err);
    CHECK(st == CB_OK, "drilled cylinder: %s", err.msg);
    int side = -1, hole = -1;
    for (int f = 0; R && f < R->n_faces; f++) {
        const cb_topo_surface *s = R->surfaces + R->faces[f].surface;
        if (s->kind == CB_SURFACE_ANALYTIC && s->analytic.kind == CB_ANALYTIC_CYLINDER &&
            fabs(s->analytic.r1 - 1) < 1e-12 && R->faces[f].count == 2)
            side = f;
    }
    CHECK(side >= 0, "drilled cylinder: no side face with two loops");
    if (side >= 0) {
        /* the hole: the loop that does not use the seam (an edge used twice by the face) */
        const cb_topo_face *fc = R->faces + side;
        for (int l = fc->first; l < fc->first + fc->count && hole < 0; l++) {
            int seam = 0;
            for (int k = R->loops[l].first; k < R->loops[l].first + R->loops[l].count; k++)
                for (int m = fc->first; m < fc->first + fc->count; m++)
                    for (int j = R->loops[m].first; j < R->loops[m].first + R->loops[m].count; j++)
                        seam |= j != k && R->coedges[j].edge == R->coedges[k].edge;
            if (!seam)
                hole = l;
        }
        CHECK(hole >= 0, "drilled cylinder: no hole loop");
    }
    cb_face F;
    for (int pass = 0; pass < 2 && hole >= 0; pass++) {
        if (pass == 1)
            for (int k = R->loops[hole].first; k < R->loops[hole].first + R->loops[hole].count;
                 k++) {
                cb_topo_curve *pc = R->pcurves + R->coedges[k].pcurve;
                if (pc->kind == CB_CURVE_NURBS)
                    for (int i = 0; i < pc->nurbs->n; i++)
                        pc->nurbs->cw[4 * i] -= 2 * PI * pc->nurbs->cw[4 * i + 3];
                else
                    pc->frame.o[0] -= 2 * PI;
            }
        st = cb_face_init(&F, R, side, R->tol, &err);
        CHECK(st == CB_OK, "drilled cylinder, pass %d: %s", pass, err.msg);
        if (st)
            break;
        /* The outer loop's segments come first (coedges of the loop holding the seam);
         * every segment of the hole must lie within their range in u. */
        double ext[2][2] = {{HUGE_VAL, -HUGE_VAL}, {HUGE_VAL, -HUGE_VAL}}; /* outer, hole */
        for (int k = 0; k < F.n_segs; k++) {
            int co = F.segs[k].coedge;
            if (co < 0)
                continue;
            double *e = ext[co >= R->loops[hole].first &&
                            co < R->loops[hole].first + R->loops[hole].count];
            e[0] = fmin(e[0], fmin(F.segs[k].p[0], F.segs[k].q[0]));
            e[1] = fmax(e[1], fmax(F.segs[k].p[0], F.segs[k].q[0]));
        }
        CHECK(ext[1][0] >= ext[0][0] && ext[1][1] <= ext[0][1],
              "drilled cylinder, pass %d: the hole spans u in [%g, %g], the outer loop [%g, %g]",
              pass, ext[1][0], ext[1][1], ext[0][0], ext[0][1]);
        /* angle ang, z = 2: in the hole; angle ang, z = 3 and angle pi / 2, z = 2: on the face */
        CHECK(cb_face_classify_uv(&F, ang, 2, 1e-9) == CB_FACE_OUT &&
                  cb_face_classify_uv(&F, ang, 3, 1e-9) == CB_FACE_IN &&
                  cb_face_classify_uv(&F, 0.5 * PI, 2, 1e-9) == CB_FACE_IN,
              "drilled cylinder, pass %d (hole's pcurves %s): the hole is not where it lies", pass,
              pass ? "moved by -2 pi" : "as made");
        cb_face_clear(&F);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
    cb_topo_body_free(R);
}

int main(void)
{
    test_edge_points_on();
    test_prim_classify();
    test_poles();
    test_rays();
    test_distance();
    test_boxes();
    test_models();
    test_bad_input();
    test_hole_lift();
    return check_report("test_brep_face");
}
