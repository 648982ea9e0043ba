/* Analytic surfaces: frames, evaluation and derivatives, trivariate polynomials, implicit
 * equations and exact rational B-spline forms.
 *
 * Scales of the implicit residual. analytic.h normalises F so that |grad F| on a patch is at
 * most gref (1 for plane, cylinder, sphere, ellipsoid; the largest distance from the axis for
 * the cone and torus). For F about a center c near the patch (cb_analytic_implicit_about),
 * resid(p) = |F(p - c)| / (gref L), L = |O| + the patch extent, bounds the distance of p from
 * the surface relative to the model size, up to the ratio of the largest to the smallest
 * |grad F| on the patch; this is the strong check. For F in world coordinates, whose rounding
 * grows with the distance from the world origin (analytic.h, "Conditioning"), the check is
 * backward: |F(p)| against the size of its terms, sum |c| |p|^alpha, and F must equal the
 * centred equation to that rounding. */
#include "brep/analytic.h"
#include "check.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

static const double pi = 3.14159265358979323846;

static const cb_analytic_kind all_kinds[] = {CB_ANALYTIC_PLANE, CB_ANALYTIC_CYLINDER,
                                             CB_ANALYTIC_CONE,  CB_ANALYTIC_SPHERE,
                                             CB_ANALYTIC_TORUS, CB_ANALYTIC_ELLIPSOID};
enum { N_KINDS = 6 };

/* Worst values seen, printed at the end for the report. */
static double max_eval_resid, max_world_back, max_world_fwd, max_nurbs_resid, max_nurbs_shape,
    max_corner_dev, max_knot_dev, max_arc_resid, max_arc_radius, max_deriv_err, max_frame_err;

static double fmax3(double a, double b, double c) { return fmax(a, fmax(b, c)); }

static void random_unit(double v[3], check_rng *rng)
{
    double n;
    do {
        for (int i = 0; i < 3; i++)
            v[i] = check_rng_uniform(rng, -1, 1);
        n = cb_vec3_norm(v);
    } while (n < 0.1 || n > 1);
    for (int i = 0; i < 3; i++)
        v[i] /= n;
}

/* The world axes under a random rotation (cb_xform_rotation), at a random origin. */
static void random_frame(cb_frame *f, check_rng *rng, double origin_box)
{
    double axis[3], zero[3] = {0, 0, 0}, ez[3] = {0, 0, 1}, ex[3] = {1, 0, 0}, o[3], z[3], x[3];
    random_unit(axis, rng);
    cb_xform R;
    cb_xform_rotation(&R, zero, axis, check_rng_uniform(rng, 0, 2 * pi));
    cb_xform_apply_vector(z, &R, ez);
    cb_xform_apply_vector(x, &R, ex);
    for (int i = 0; i < 3; i++)
        o[i] = check_rng_uniform(rng, -origin_box, origin_box);
    cb_error err;
    cb_status st = cb_frame_make(f, o, z, x, &err);
    CHECK(st == CB_OK, "random frame rejected: %s", err.msg);
}

/* A valid patch of a random surface with the scales of the header comment. */
typedef struct {
    cb_analytic_surface s;
    double u0, u1, v0, v1;
    double ext, L, gref;
    double c[3]; /* a center within ext of the frame origin, for cb_analytic_implicit_about */
} patch;

static void random_angle_range(double *a0, double *a1, check_rng *rng)
{
    *a0 = check_rng_uniform(rng, -2 * pi, 2 * pi);
    *a1 = check_rng_int(rng, 0, 3) == 0 ? *a0 + 2 * pi : *a0 + check_rng_uniform(rng, 0.05, 2 * pi);
}

static void random_patch(patch *P, cb_analytic_kind kind, check_rng *rng)
{
    cb_frame f;
    random_frame(&f, rng, 10);
    cb_error err;
    cb_status st = CB_OK;
    cb_analytic_surface *s = &P->s;
    random_angle_range(&P->u0, &P->u1, rng);
    P->gref = 1.0;
    switch (kind) {
    case CB_ANALYTIC_PLANE:
        P->u0 = check_rng_uniform(rng, -5, 4);
        P->u1 = check_rng_uniform(rng, P->u0 + 0.1, 5);
        P->v0 = check_rng_uniform(rng, -5, 4);
        P->v1 = check_rng_uniform(rng, P->v0 + 0.1, 5);
        st = cb_analytic_plane(s, &f, &err);
        P->ext = fmax(fmax(fabs(P->u0), fabs(P->u1)), fmax(fabs(P->v0), fabs(P->v1)));
        break;
    case CB_ANALYTIC_CYLINDER: {
        double r = check_rng_uniform(rng, 0.2, 5);
        P->v0 = check_rng_uniform(rng, -5, 4);
        P->v1 = check_rng_uniform(rng, P->v0 + 0.1, 5);
        st = cb_analytic_cylinder(s, &f, r, &err);
        P->ext = r + fmax(fabs(P->v0), fabs(P->v1));
        break;
    }
    case CB_ANALYTIC_CONE: {
        /* Sometimes an apex at the origin (r = 0), sometimes a patch ending at the apex. */
        double r = check_rng_int(rng, 0, 4) == 0 ? 0.0 : check_rng_uniform(rng, 0.2, 5);
        double a = check_rng_uniform(rng, 0.1, 1.4), t = tan(a), apex = -r / t;
        P->v0 = check_rng_int(rng, 0, 3) == 0 ? apex : apex + check_rng_uniform(rng, 0, 3);
        P->v1 = P->v0 + check_rng_uniform(rng, 0.2, 4);
        st = cb_analytic_cone(s, &f, r, a, &err);
        P->gref = r + P->v1 * t;
        P->ext = P->gref + fmax(fabs(P->v0), fabs(P->v1));
        break;
    }
    case CB_ANALYTIC_SPHERE: {
        double r = check_rng_uniform(rng, 0.2, 5);
        if (check_rng_int(rng, 0, 3) == 0) {
            P->v0 = -0.5 * pi;
            P->v1 = 0.5 * pi;
        } else {
            P->v0 = check_rng_uniform(rng, -0.5 * pi, 1.4);
            P->v1 = check_rng_uniform(rng, P->v0 + 0.1, 0.5 * pi);
        }
        st = cb_analytic_sphere(s, &f, r, &err);
        P->ext = r;
        break;
    }
    case CB_ANALYTIC_TORUS: {
        double R = check_rng_uniform(rng, 0.5, 5), r = R * check_rng_uniform(rng, 0.05, 0.9);
        random_angle_range(&P->v0, &P->v1, rng);
        st = cb_analytic_torus(s, &f, R, r, &err);
        P->gref = R + r;
        P->ext = R + r;
        break;
    }
    case CB_ANALYTIC_ELLIPSOID: {
        double a = check_rng_uniform(rng, 0.2, 5), b = check_rng_uniform(rng, 0.2, 5),
               c = check_rng_uniform(rng, 0.2, 5);
        P->v0 = check_rng_uniform(rng, -0.5 * pi, 1.4);
        P->v1 = check_rng_int(rng, 0, 2) == 0 ? 0.5 * pi
                                              : check_rng_uniform(rng, P->v0 + 0.1, 0.5 * pi);
        st = cb_analytic_ellipsoid(s, &f, a, b, c, &err);
        P->ext = fmax3(a, b, c);
        break;
    }
    }
    CHECK(st == CB_OK, "random %s rejected: %s", cb_analytic_kind_name(kind), err.msg);
    P->L = cb_vec3_norm(f.o) + P->ext;
    double w[3];
    random_unit(w, rng);
    double len = check_rng_uniform(rng, 0, P->ext);
    for (int i = 0; i < 3; i++)
        P->c[i] = f.o[i] + len * w[i];
}

/* |F(p - c)| / (gref L): the strong residual of the header comment. */
static double centred_resid(const patch *P, const cb_poly3_t Fc, const double p[3])
{
    double q[3] = {p[0] - P->c[0], p[1] - P->c[1], p[2] - P->c[2]};
    return fabs(cb_poly3_eval(Fc, q)) / (P->gref * P->L);
}

/* Signed deviation of p from the surface by each kind's closed-form geometry, independent of
 * the implicit equation (the ellipsoid: of the point scaled to the unit sphere, times the
 * smallest semi-axis). */
static double shape_error(const cb_analytic_surface *s, const double p[3])
{
    double l[3];
    cb_frame_to_local(l, &s->frame, p);
    double rho = hypot(l[0], l[1]);
    switch (s->kind) {
    case CB_ANALYTIC_PLANE: return l[2];
    case CB_ANALYTIC_CYLINDER: return rho - s->r1;
    case CB_ANALYTIC_CONE: return rho - fabs(s->r1 + l[2] * tan(s->angle));
    case CB_ANALYTIC_SPHERE: return cb_vec3_norm(l) - s->r1;
    case CB_ANALYTIC_TORUS: return hypot(rho - s->r1, l[2]) - s->r2;
    case CB_ANALYTIC_ELLIPSOID: {
        double q[3] = {l[0] / s->r1, l[1] / s->r2, l[2] / s->r3};
        return (cb_vec3_norm(q) - 1) * fmin(s->r1, fmin(s->r2, s->r3));
    }
    }
    return NAN;
}

/* The point the outward side faces away from: the centre, the foot on the axis, or the
 * nearest point of the torus's core circle; for the plane, a point below it. */
static void inner_point(double c[3], const cb_analytic_surface *s, const double p[3])
{
    double l[3];
    cb_frame_to_local(l, &s->frame, p);
    double rho = hypot(l[0], l[1]);
    switch (s->kind) {
    case CB_ANALYTIC_PLANE: l[2] -= 1; break;
    case CB_ANALYTIC_CYLINDER:
    case CB_ANALYTIC_CONE: l[0] = l[1] = 0; break;
    case CB_ANALYTIC_SPHERE:
    case CB_ANALYTIC_ELLIPSOID: l[0] = l[1] = l[2] = 0; break;
    case CB_ANALYTIC_TORUS:
        l[0] *= s->r1 / rho;
        l[1] *= s->r1 / rho;
        l[2] = 0;
        break;
    }
    cb_frame_to_world(c, &s->frame, l);
}

/* |grad F| on the surface at p as analytic.h documents it: 1, rho, or for the ellipsoid
 * min(a, b, c) |(x/a^2, y/b^2, z/c^2)|. */
static double expected_grad(const cb_analytic_surface *s, const double p[3])
{
    double l[3];
    cb_frame_to_local(l, &s->frame, p);
    switch (s->kind) {
    case CB_ANALYTIC_CONE:
    case CB_ANALYTIC_TORUS: return hypot(l[0], l[1]);
    case CB_ANALYTIC_ELLIPSOID: {
        double a = s->r1, b = s->r2, c = s->r3;
        double n[3] = {l[0] / (a * a), l[1] / (b * b), l[2] / (c * c)};
        return fmin(a, fmin(b, c)) * cb_vec3_norm(n);
    }
    default: return 1.0;
    }
}

/* Smallest radius of curvature that matters for an off-surface step at p. */
static double curvature_scale(const patch *P, const double p[3])
{
    const cb_analytic_surface *s = &P->s;
    double l[3];
    cb_frame_to_local(l, &s->frame, p);
    switch (s->kind) {
    case CB_ANALYTIC_PLANE: return P->ext;
    case CB_ANALYTIC_CYLINDER:
    case CB_ANALYTIC_SPHERE: return s->r1;
    case CB_ANALYTIC_CONE: return hypot(l[0], l[1]);
    case CB_ANALYTIC_TORUS: return fmin(s->r2, s->r1 - s->r2);
    case CB_ANALYTIC_ELLIPSOID: {
        double lo = fmin(s->r1, fmin(s->r2, s->r3)), hi = fmax3(s->r1, s->r2, s->r3);
        return lo * lo / hi;
    }
    }
    return 0;
}

/* ---------------------------------------------------------------- frames ------------------- */

static double frame_error(const cb_frame *f)
{
    double c[3], e = 0;
    cb_vec3_cross(c, f->x, f->y);
    e = fmax(e, fabs(cb_vec3_dot(f->x, f->x) - 1));
    e = fmax(e, fabs(cb_vec3_dot(f->y, f->y) - 1));
    e = fmax(e, fabs(cb_vec3_dot(f->z, f->z) - 1));
    e = fmax(e, fmax3(fabs(cb_vec3_dot(f->x, f->y)), fabs(cb_vec3_dot(f->y, f->z)),
                      fabs(cb_vec3_dot(f->z, f->x))));
    e = fmax(e, cb_vec3_dist(c, f->z));
    return e;
}

/* Orthonormal and right-handed; z along the axis; x in the half plane of the reference; the
 * reference may be as close to the axis as 1e-12 rad (the second Gram-Schmidt pass). */
static void test_frames(check_rng *rng)
{
    cb_error err;
    for (int trial = 0; trial < 300; trial++) {
        double o[3], axis[3], ref[3], perp[3];
        for (int i = 0; i < 3; i++)
            o[i] = check_rng_uniform(rng, -100, 100);
        random_unit(axis, rng);
        double scale = pow(10.0, check_rng_uniform(rng, -6, 6));
        for (int i = 0; i < 3; i++)
            axis[i] *= scale;
        random_unit(ref, rng);
        int mode = trial % 3; /* 0: general, 1: nearly parallel reference, 2: NULL reference */
        if (mode == 1) {
            cb_vec3_cross(perp, axis, ref);
            cb_vec3_normalize(perp);
            double tiny = pow(10.0, check_rng_uniform(rng, -12, -3));
            for (int i = 0; i < 3; i++)
                ref[i] = -axis[i] / scale + tiny * perp[i];
        }
        cb_frame f;
        cb_status st = cb_frame_make(&f, o, axis, mode == 2 ? NULL : ref, &err);
        CHECK(st == CB_OK, "trial %d: %s", trial, err.msg);
        if (st)
            continue;
        double e = frame_error(&f);
        max_frame_err = fmax(max_frame_err, e);
        CHECK(e <= 4 * DBL_EPSILON, "trial %d mode %d: frame not orthonormal, error %g", trial,
              mode, e);
        double za[3] = {axis[0] / scale, axis[1] / scale, axis[2] / scale};
        CHECK(cb_vec3_dist(f.z, za) <= 4 * DBL_EPSILON, "trial %d: z %g off the axis", trial,
              cb_vec3_dist(f.z, za));
        if (mode != 2) {
            /* x is the normalised projection of ref: x.ref > 0 and ref in span(x, z). */
            double c[3];
            cb_vec3_cross(c, f.x, f.z);
            double off = fabs(cb_vec3_dot(c, ref)) / cb_vec3_norm(ref);
            CHECK(cb_vec3_dot(f.x, ref) > 0 && off <= 4 * DBL_EPSILON,
                  "trial %d mode %d: x not from ref (x.ref %g, off-plane %g)", trial, mode,
                  cb_vec3_dot(f.x, ref), off);
        }
        double l[3], p[3], back[3];
        for (int i = 0; i < 3; i++)
            l[i] = check_rng_uniform(rng, -10, 10);
        cb_frame_to_world(p, &f, l);
        cb_frame_to_local(back, &f, p);
        CHECK(cb_vec3_dist(l, back) <= 1e-13, "trial %d: local -> world -> local moved %g", trial,
              cb_vec3_dist(l, back));
    }
}

/* ---------------------------------------------------------------- polynomials -------------- */

static void random_poly(cb_poly3_t p, int deg, check_rng *rng)
{
    cb_status st = cb_poly3_alloc(p, deg, NULL);
    CHECK(st == CB_OK, "alloc degree %d", deg);
    for (int q = 0; q < cb_poly3_len(deg); q++)
        p->c[q] = check_rng_uniform(rng, -1, 1);
}

/* sum |c| |x|^alpha: the size of the terms, the scale of the rounding of p(x). */
static double abs_eval(const cb_poly3_t p, const double x[3])
{
    cb_poly3_t a;
    cb_poly3_init(a);
    cb_poly3_set(a, p, NULL);
    for (int q = 0; q < cb_poly3_len(a->deg); q++)
        a->c[q] = fabs(a->c[q]);
    double ax[3] = {fabs(x[0]), fabs(x[1]), fabs(x[2])};
    double v = cb_poly3_eval(a, ax);
    cb_poly3_clear(a);
    return v;
}

static void test_poly3(check_rng *rng)
{
    /* The index formula enumerates storage order and the length counts it. */
    for (int d = 0; d <= 10; d++) {
        int idx = 0, ok = 1;
        for (int t = 0; t <= d; t++)
            for (int m = 0; m <= t; m++)
                for (int k = 0; k <= m; k++, idx++)
                    ok &= cb_poly3_index(t - m, m - k, k) == idx;
        CHECK(ok && idx == cb_poly3_len(d), "layout of degree %d: %d monomials, len %d", d, idx,
              cb_poly3_len(d));
    }
    cb_poly3_t P, Q, R, S;
    cb_poly3_init(P);
    cb_poly3_init(Q);
    cb_poly3_init(R);
    cb_poly3_init(S);
    double zero[3] = {0.5, -1, 2};
    CHECK(cb_poly3_eval(P, zero) == 0.0, "the initialised polynomial is not zero");
    for (int trial = 0; trial < 300; trial++) {
        int dp = check_rng_int(rng, 0, 4), dq = check_rng_int(rng, 0, 4);
        random_poly(P, dp, rng);
        random_poly(Q, dq, rng);
        double x[3];
        for (int i = 0; i < 3; i++)
            x[i] = check_rng_uniform(rng, -2, 2);

        /* (P Q)(x) = P(x) Q(x), and the product may overwrite a factor. */
        cb_poly3_mul(R, P, Q, NULL);
        double e = fabs(cb_poly3_eval(R, x) - cb_poly3_eval(P, x) * cb_poly3_eval(Q, x));
        double sc = abs_eval(P, x) * abs_eval(Q, x);
        CHECK(e <= 1e-14 * sc, "trial %d: product off by %g (scale %g)", trial, e, sc);
        cb_poly3_set(S, P, NULL);
        cb_poly3_mul(S, S, Q, NULL);
        CHECK(S->deg == R->deg &&
                  !memcmp(S->c, R->c, (size_t)cb_poly3_len(R->deg) * sizeof(double)),
              "trial %d: aliased product differs", trial);

        /* (P o A)(x) = P(m x + t). */
        double m[3][3], t[3], y[3], ay[3];
        for (int a = 0; a < 3; a++) {
            t[a] = check_rng_uniform(rng, -3, 3);
            for (int b = 0; b < 3; b++)
                m[a][b] = check_rng_uniform(rng, -1, 1);
        }
        for (int a = 0; a < 3; a++) {
            y[a] = t[a] + m[a][0] * x[0] + m[a][1] * x[1] + m[a][2] * x[2];
            ay[a] = fabs(t[a]) + fabs(m[a][0] * x[0]) + fabs(m[a][1] * x[1]) + fabs(m[a][2] * x[2]);
        }
        cb_status st = cb_poly3_compose_affine(R, P, m, t, NULL);
        e = fabs(cb_poly3_eval(R, x) - cb_poly3_eval(P, y));
        sc = abs_eval(P, ay);
        CHECK(st == CB_OK && R->deg == dp && e <= 1e-13 * sc,
              "trial %d: composition off by %g (scale %g)", trial, e, sc);

        /* The identity substitution returns P exactly. */
        double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, t0[3] = {0, 0, 0};
        cb_poly3_compose_affine(R, P, id, t0, NULL);
        CHECK(!memcmp(R->c, P->c, (size_t)cb_poly3_len(dp) * sizeof(double)),
              "trial %d: identity composition changed P", trial);

        /* The gradient against a fourth-order central difference. */
        double g[3], f0 = cb_poly3_eval_grad(g, P, x), h = 1e-3;
        CHECK(f0 == cb_poly3_eval(P, x), "trial %d: eval_grad value %.17g != eval %.17g", trial, f0,
              cb_poly3_eval(P, x));
        for (int a = 0; a < 3; a++) {
            double xs[4][3];
            for (int q = 0; q < 4; q++) {
                memcpy(xs[q], x, sizeof xs[q]);
                xs[q][a] += h * (q < 2 ? q - 2 : q - 1);
            }
            double fd = (cb_poly3_eval(P, xs[0]) - 8 * cb_poly3_eval(P, xs[1]) +
                         8 * cb_poly3_eval(P, xs[2]) - cb_poly3_eval(P, xs[3])) /
                        (12 * h);
            CHECK(fabs(fd - g[a]) <= 1e-8 * abs_eval(P, x) + 1e-8,
                  "trial %d: d/dx%d %g vs difference %g", trial, a, g[a], fd);
        }
    }
    cb_poly3_clear(P);
    cb_poly3_clear(Q);
    cb_poly3_clear(R);
    cb_poly3_clear(S);
}

/* ---------------------------------------------------------------- implicit equations ------- */

/* Points of the parameterisation satisfy F = 0 to 1e-12 (scaled); steps off the surface along
 * the normal change F by |grad F| times the step and flip its sign across the surface; grad F
 * has the documented length and points outward. */
/* |Fw(p) - Fc(p - c)| / sum |c| |p|^alpha of Fw: world and centred equations agree to the
 * rounding of the world one. */
static double world_vs_centred(const patch *P, const cb_poly3_t Fw, const cb_poly3_t Fc,
                               const double p[3])
{
    double q[3] = {p[0] - P->c[0], p[1] - P->c[1], p[2] - P->c[2]};
    return fabs(cb_poly3_eval(Fw, p) - cb_poly3_eval(Fc, q)) / abs_eval(Fw, p);
}

static void test_implicit(check_rng *rng)
{
    cb_poly3_t F, Fw;
    cb_poly3_init(F);
    cb_poly3_init(Fw);
    cb_error err;
    for (int kk = 0; kk < N_KINDS; kk++)
        for (int trial = 0; trial < 60; trial++) {
            patch P;
            random_patch(&P, all_kinds[kk], rng);
            const char *name = cb_analytic_kind_name(P.s.kind);
            cb_status st = cb_analytic_implicit_about(F, &P.s, P.c, &err);
            if (!st)
                st = cb_analytic_implicit(Fw, &P.s, &err);
            int want_deg = P.s.kind == CB_ANALYTIC_PLANE   ? 1
                           : P.s.kind == CB_ANALYTIC_TORUS ? 4
                                                           : 2;
            CHECK(st == CB_OK && F->deg == want_deg && Fw->deg == want_deg,
                  "%s trial %d: implicit failed (%s) or degree %d", name, trial, err.msg, F->deg);
            if (st)
                continue;
            for (int k = 0; k < 40; k++) {
                double u = check_rng_uniform(rng, -10, 10), v = check_rng_uniform(rng, P.v0, P.v1);
                double d[6][3], g[3], n[3], q[3];
                cb_analytic_eval_derivs(d, &P.s, u, v);
                for (int i = 0; i < 3; i++)
                    q[i] = d[0][i] - P.c[i];
                cb_poly3_eval_grad(g, F, q);
                double resid = centred_resid(&P, F, d[0]);
                double fw = cb_poly3_eval(Fw, d[0]), back = fabs(fw) / abs_eval(Fw, d[0]);
                max_eval_resid = fmax(max_eval_resid, resid);
                max_world_back = fmax(max_world_back, back);
                max_world_fwd = fmax(max_world_fwd, fabs(fw) / (P.gref * P.L));
                CHECK(resid <= 1e-12 && back <= 1e-14,
                      "%s trial %d (u, v) = (%g, %g): scaled F %g, world F %g of its terms", name,
                      trial, u, v, resid, back);

                cb_vec3_cross(n, d[1], d[2]);
                double kap = curvature_scale(&P, d[0]);
                if (cb_vec3_normalize(n) == 0 || kap < 1e-2 * P.ext)
                    continue; /* pole or apex: no normal, or no room for a step */
                double gn = cb_vec3_norm(g), want = expected_grad(&P.s, d[0]);
                CHECK(fabs(gn - want) <= 1e-9 * P.gref,
                      "%s trial %d: |grad F| = %.17g, documented %.17g", name, trial, gn, want);
                double c[3], out[3];
                inner_point(c, &P.s, d[0]);
                for (int i = 0; i < 3; i++)
                    out[i] = d[0][i] - c[i];
                CHECK(cb_vec3_dot(g, out) > 0, "%s trial %d: grad F points inward", name, trial);

                /* The step is small against the curvature, so F changes by |grad F| times it,
                 * and large against the on-surface bound: by the ranges of random_patch,
                 * |F| >= 1e-7 ext^2 >= 3e-9 gref L here. */
                double delta = 1e-3 * kap, fp[2];
                for (int sgn = 0; sgn < 2; sgn++) {
                    double x[3], y[3];
                    for (int i = 0; i < 3; i++) {
                        x[i] = d[0][i] + (sgn ? -delta : delta) * n[i];
                        y[i] = x[i] - P.c[i];
                    }
                    fp[sgn] = cb_poly3_eval(F, y);
                    double agree = world_vs_centred(&P, Fw, F, x);
                    CHECK(agree <= 1e-14,
                          "%s trial %d: world and centred F differ by %g of the "
                          "terms",
                          name, trial, agree);
                }
                double ratio = fabs(fp[0]) / (gn * delta);
                CHECK(fp[0] * fp[1] < 0 && fabs(ratio - 1) < 2e-2 &&
                          fabs(fp[0]) > 1e3 * 1e-12 * P.gref * P.L,
                      "%s trial %d: off-surface F = %g, %g for step %g (|grad| %g)", name, trial,
                      fp[0], fp[1], delta, gn);
            }
        }
    cb_poly3_clear(Fw);

    /* The ellipsoid with equal semi-axes is the sphere, in evaluation and equation. */
    for (int trial = 0; trial < 50; trial++) {
        cb_frame f;
        random_frame(&f, rng, 10);
        double r = check_rng_uniform(rng, 0.2, 5);
        cb_analytic_surface sph, ell;
        cb_analytic_sphere(&sph, &f, r, NULL);
        cb_analytic_ellipsoid(&ell, &f, r, r, r, NULL);
        double u = check_rng_uniform(rng, -4, 4), v = check_rng_uniform(rng, -2, 2), a[3], b[3];
        cb_analytic_eval(a, &sph, u, v);
        cb_analytic_eval(b, &ell, u, v);
        CHECK(cb_vec3_dist(a, b) <= 1e-14 * (cb_vec3_norm(f.o) + r),
              "trial %d: ellipsoid (r, r, r) and sphere differ by %g", trial, cb_vec3_dist(a, b));
        cb_poly3_t G;
        cb_poly3_init(G);
        cb_analytic_implicit(F, &sph, NULL);
        cb_analytic_implicit(G, &ell, NULL);
        double e = 0, sc = 0;
        for (int q = 0; q < cb_poly3_len(2); q++) {
            e = fmax(e, fabs(F->c[q] - G->c[q]));
            sc = fmax(sc, fabs(F->c[q]));
        }
        CHECK(e <= 1e-14 * sc, "trial %d: sphere and round ellipsoid equations differ by %g", trial,
              e);
        cb_poly3_clear(G);
    }
    cb_poly3_clear(F);
}

/* ---------------------------------------------------------------- derivatives -------------- */

/* Each derivative against a fourth-order central difference of the order below it: S_u, S_v
 * of the points, S_uu, S_uv of S_u, S_uv, S_vv of S_v. d[0] equals cb_analytic_eval. */
static void test_derivs(check_rng *rng)
{
    const double h = 1e-3, wt[4] = {1, -8, 8, -1}, off[4] = {-2, -1, 1, 2};
    for (int kk = 0; kk < N_KINDS; kk++)
        for (int trial = 0; trial < 60; trial++) {
            patch P;
            random_patch(&P, all_kinds[kk], rng);
            const char *name = cb_analytic_kind_name(P.s.kind);
            double u = check_rng_uniform(rng, -10, 10);
            double v = check_rng_uniform(rng, P.v0 + 2 * h, P.v1 - 2 * h);
            double d[6][3], p[3];
            cb_analytic_eval_derivs(d, &P.s, u, v);
            cb_analytic_eval(p, &P.s, u, v);
            CHECK(!memcmp(p, d[0], sizeof p), "%s trial %d: eval and eval_derivs differ", name,
                  trial);
            /* fd[dir][k]: difference along dir (0 = u, 1 = v) of d[k], k = 0, 1, 2. */
            double fd[2][3][3];
            memset(fd, 0, sizeof fd);
            for (int dir = 0; dir < 2; dir++)
                for (int q = 0; q < 4; q++) {
                    double e[6][3];
                    cb_analytic_eval_derivs(e, &P.s, u + (dir ? 0 : off[q] * h),
                                            v + (dir ? off[q] * h : 0));
                    for (int k = 0; k < 3; k++)
                        for (int i = 0; i < 3; i++)
                            fd[dir][k][i] += wt[q] * e[k][i] / (12 * h);
                }
            /* {derivative index, direction, differentiated index} */
            const int pairs[6][3] = {{1, 0, 0}, {2, 1, 0}, {3, 0, 1},
                                     {4, 1, 1}, {4, 0, 2}, {5, 1, 2}};
            for (int q = 0; q < 6; q++) {
                const double *a = d[pairs[q][0]], *b = fd[pairs[q][1]][pairs[q][2]];
                double err = cb_vec3_dist(a, b) / P.L;
                max_deriv_err = fmax(max_deriv_err, err);
                CHECK(err <= 1e-8, "%s trial %d (u, v) = (%g, %g): derivative %d off by %g", name,
                      trial, u, v, pairs[q][0], err);
            }
        }
}

/* ---------------------------------------------------------------- rational B-spline forms -- */

/* a unwrapped by whole turns to the value nearest ref. */
static double unwrap(double a, double ref) { return a + 2 * pi * round((ref - a) / (2 * pi)); }

/* Parameter angles of a point: the parallel angle u and, for the meridian circles, v; for the
 * cylinder and cone v is z'. Returns the distance from the axis. */
static double point_angles(double *u, double *v, const cb_analytic_surface *s, const double p[3])
{
    double l[3];
    cb_frame_to_local(l, &s->frame, p);
    double sx = 1, sy = 1, sz = 1, A = 0, B = 1;
    if (s->kind == CB_ANALYTIC_ELLIPSOID) {
        sx = s->r1;
        sy = s->r2;
        sz = s->r3;
    } else if (s->kind == CB_ANALYTIC_TORUS) {
        A = s->r1;
        B = s->r2;
        sz = s->r2;
    } else if (s->kind == CB_ANALYTIC_SPHERE) {
        B = sz = s->r1;
    }
    double rho = hypot(l[0] / sx, l[1] / sy);
    *u = atan2(l[1] / sy, l[0] / sx);
    *v = s->kind == CB_ANALYTIC_CYLINDER || s->kind == CB_ANALYTIC_CONE
             ? l[2]
             : atan2(l[2] / sz, (rho - A) / B);
    return hypot(l[0], l[1]);
}

enum { GRID = 41 };

/* One NURBS patch: validation; a dense grid on the implicit equation and at the right distance;
 * the parallel and meridian angles of the grid increase strictly from (u0, v0) to (u1, v1), so
 * the patch covers the range and stays inside it; at every knot pair, the corners among them,
 * the point is the analytic point of the same parameters. */
static void check_nurbs_patch(const patch *P, const cb_poly3_t F, int trial)
{
    const cb_analytic_surface *s = &P->s;
    const char *name = cb_analytic_kind_name(s->kind);
    cb_nurbs_surface_t N;
    cb_nurbs_surface_init(N);
    cb_error err;
    cb_status st = cb_analytic_to_nurbs(N, s, P->u0, P->u1, P->v0, P->v1, &err);
    CHECK(st == CB_OK, "%s trial %d: to_nurbs [%g, %g] x [%g, %g]: %s", name, trial, P->u0, P->u1,
          P->v0, P->v1, err.msg);
    if (st)
        return;
    st = cb_nurbs_surface_validate(N, &err);
    CHECK(st == CB_OK, "%s trial %d: invalid NURBS: %s", name, trial, err.msg);
    double box[4];
    cb_nurbs_surface_domain(N, box);
    CHECK(box[0] == P->u0 && box[1] == P->u1 && box[2] == P->v0 && box[3] == P->v1,
          "%s trial %d: domain [%g, %g] x [%g, %g]", name, trial, box[0], box[1], box[2], box[3]);

    static double au[GRID][GRID], av[GRID][GRID], rh[GRID][GRID];
    for (int i = 0; i < GRID; i++)
        for (int j = 0; j < GRID; j++) {
            double u = box[0] + (box[1] - box[0]) * i / (GRID - 1);
            double v = box[2] + (box[3] - box[2]) * j / (GRID - 1);
            double p[3];
            cb_nurbs_surface_eval(p, N, u, v);
            double resid = centred_resid(P, F, p);
            double shape = fabs(shape_error(s, p)) / P->L;
            max_nurbs_resid = fmax(max_nurbs_resid, resid);
            max_nurbs_shape = fmax(max_nurbs_shape, shape);
            CHECK(resid <= 1e-12 && shape <= 1e-13,
                  "%s trial %d (%g, %g): scaled F %g, distance error %g", name, trial, u, v, resid,
                  shape);
            if (s->kind == CB_ANALYTIC_PLANE) {
                double l[3];
                cb_frame_to_local(l, &s->frame, p);
                CHECK(fabs(l[0] - u) <= 1e-13 * P->L && fabs(l[1] - v) <= 1e-13 * P->L,
                      "plane trial %d: (%g, %g) maps to local (%g, %g)", trial, u, v, l[0], l[1]);
                continue;
            }
            rh[i][j] = point_angles(&au[i][j], &av[i][j], s, p);
        }
    if (s->kind != CB_ANALYTIC_PLANE) {
        /* Rows along u (skipping the collapsed rows at poles and apex), then columns along v. */
        const double tol = 1e-11;
        for (int j = 0; j < GRID; j++) {
            if (rh[0][j] < 1e-9 * P->ext)
                continue;
            double prev = unwrap(au[0][j], P->u0);
            int ok = fabs(prev - P->u0) <= tol;
            for (int i = 1; i < GRID; i++) {
                double a = unwrap(au[i][j], prev);
                ok &= a > prev;
                prev = a;
            }
            ok &= fabs(prev - P->u1) <= tol;
            CHECK(ok, "%s trial %d: u angles of row %d do not run from %.17g to %.17g", name, trial,
                  j, P->u0, P->u1);
        }
        for (int i = 0; i < GRID; i++) {
            double prev = unwrap(av[i][0], P->v0);
            int ok = fabs(prev - P->v0) <= tol * P->ext;
            for (int j = 1; j < GRID; j++) {
                double a = av[i][j];
                if (s->kind == CB_ANALYTIC_TORUS)
                    a = unwrap(a, prev);
                ok &= a > prev;
                prev = a;
            }
            ok &= fabs(prev - P->v1) <= tol * P->ext;
            CHECK(ok, "%s trial %d: v of column %d does not run from %.17g to %.17g", name, trial,
                  i, P->v0, P->v1);
        }
    }

    for (int a = N->deg_u; a <= N->n_u; a++)
        for (int b = N->deg_v; b <= N->n_v; b++) {
            double u = N->knots_u[a], v = N->knots_v[b], p[3], q[3];
            cb_nurbs_surface_eval(p, N, u, v);
            cb_analytic_eval(q, s, u, v);
            double dev = cb_vec3_dist(p, q) / P->L;
            int corner = (a == N->deg_u || a == N->n_u) && (b == N->deg_v || b == N->n_v);
            if (corner)
                max_corner_dev = fmax(max_corner_dev, dev);
            else
                max_knot_dev = fmax(max_knot_dev, dev);
            CHECK(dev <= 1e-15,
                  "%s trial %d: at knots (%.17g, %.17g) NURBS and analytic differ "
                  "by %g (corner %d)",
                  name, trial, u, v, dev, corner);
        }
    cb_nurbs_surface_clear(N);
}

static void test_to_nurbs(check_rng *rng)
{
    cb_poly3_t F;
    cb_poly3_init(F);
    for (int kk = 0; kk < N_KINDS; kk++)
        for (int trial = 0; trial < 40; trial++) {
            patch P;
            random_patch(&P, all_kinds[kk], rng);
            cb_analytic_implicit_about(F, &P.s, P.c, NULL);
            check_nurbs_patch(&P, F, trial);
        }
    cb_poly3_clear(F);
}

/* Circle arcs, full and partial: valid, 1 to 4 segments as the angle needs, on the circle's
 * plane and cylinder equations and at the radius, the angle running strictly from a0 to a1 with
 * the parameter equal to the angle at the knots; with non-orthonormal directions, on the
 * ellipse c + r (cos t xdir + sin t ydir). */
static void test_arcs(check_rng *rng)
{
    cb_poly3_t Fp, Fc;
    cb_poly3_init(Fp);
    cb_poly3_init(Fc);
    cb_nurbs_curve_t C;
    cb_nurbs_curve_init(C);
    cb_error err;
    for (int trial = 0; trial < 200; trial++) {
        cb_frame f;
        random_frame(&f, rng, 10);
        double r = check_rng_uniform(rng, 0.1, 5), a0, a1;
        random_angle_range(&a0, &a1, rng);
        int ellipse = trial % 4 == 3;
        double xd[3], yd[3], sx = 1, sy = 1, shear = 0;
        if (ellipse) {
            sx = check_rng_uniform(rng, 0.3, 3);
            sy = check_rng_uniform(rng, 0.3, 3);
            shear = check_rng_uniform(rng, -0.5, 0.5);
        }
        for (int i = 0; i < 3; i++) {
            xd[i] = sx * f.x[i];
            yd[i] = sy * f.y[i] + shear * f.x[i];
        }
        cb_status st = cb_nurbs_curve_arc(C, f.o, xd, yd, r, a0, a1, &err);
        CHECK(st == CB_OK, "trial %d: arc [%.17g, %.17g]: %s", trial, a0, a1, err.msg);
        if (st)
            continue;
        st = cb_nurbs_curve_validate(C, &err);
        CHECK(st == CB_OK, "trial %d: invalid arc: %s", trial, err.msg);
        int segs = (int)ceil((a1 - a0) / (0.5 * pi) - 1e-9);
        CHECK(C->deg == 2 && C->n == 2 * segs + 1, "trial %d: span %g gives %d points, want %d",
              trial, a1 - a0, C->n, 2 * segs + 1);
        double ca, cb;
        cb_nurbs_curve_domain(C, &ca, &cb);
        CHECK(ca == a0 && cb == a1, "trial %d: domain [%g, %g]", trial, ca, cb);

        cb_analytic_surface pl, cy;
        cb_analytic_plane(&pl, &f, NULL);
        cb_analytic_cylinder(&cy, &f, r, NULL);
        cb_analytic_implicit_about(Fp, &pl, f.o, NULL);
        cb_analytic_implicit_about(Fc, &cy, f.o, NULL);
        double L = cb_vec3_norm(f.o) + r * fmax(sx, sy + fabs(shear)), prev = a0;
        int ok = 1;
        for (int k = 0; k <= 200; k++) {
            double t = a0 + (a1 - a0) * k / 200, p[3], l[3], q[3];
            cb_nurbs_curve_eval(p, C, t);
            for (int i = 0; i < 3; i++)
                q[i] = p[i] - f.o[i];
            cb_frame_to_local(l, &f, p);
            /* Undo the linear map of (cos, sin) to local (x, y). */
            double cy_ = l[1] / (r * sy), cx_ = (l[0] / r - shear * cy_) / sx;
            double ang = unwrap(atan2(cy_, cx_), prev);
            ok &= k == 0 ? fabs(ang - a0) <= 1e-12 : ang > prev;
            prev = ang;
            double unit = fabs(hypot(cx_, cy_) - 1) * r / L;
            double resid = fabs(cb_poly3_eval(Fp, q)) / L;
            if (!ellipse) {
                resid = fmax(resid, fabs(cb_poly3_eval(Fc, q)) / L);
                max_arc_radius = fmax(max_arc_radius, fabs(cb_vec3_dist(p, f.o) - r) / L);
            }
            max_arc_resid = fmax(max_arc_resid, fmax(resid, unit));
            CHECK(resid <= 1e-12 && unit <= 1e-13,
                  "trial %d t %g: scaled F %g, off the circle by %g", trial, t, resid, unit);
        }
        CHECK(ok && fabs(prev - a1) <= 1e-12,
              "trial %d: angles not increasing from %.17g to %.17g (end %.17g)", trial, a0, a1,
              prev);
        for (int k = C->deg; k <= C->n; k++) {
            double t = C->knots[k], p[3], q[3];
            cb_nurbs_curve_eval(p, C, t);
            for (int i = 0; i < 3; i++)
                q[i] = f.o[i] + r * (cos(t) * xd[i] + sin(t) * yd[i]);
            CHECK(cb_vec3_dist(p, q) <= 1e-15 * L, "trial %d: at knot %.17g off by %g", trial, t,
                  cb_vec3_dist(p, q));
        }
    }
    /* Segment counts at the quarter-turn boundaries. */
    double o[3] = {0, 0, 0}, xd[3] = {1, 0, 0}, yd[3] = {0, 1, 0};
    for (int q = 1; q <= 4; q++) {
        cb_status st = cb_nurbs_curve_arc(C, o, xd, yd, 1, 0, q * (0.5 * pi), &err);
        CHECK(st == CB_OK && C->n == 2 * q + 1, "arc of %d quarter turns: %d points (%s)", q, C->n,
              err.msg);
    }
    cb_nurbs_curve_clear(C);
    cb_poly3_clear(Fp);
    cb_poly3_clear(Fc);
}

/* ---------------------------------------------------------------- bad input ---------------- */

static void expect_invalid(cb_status st, const cb_error *err, const char *what,
                           const char *const *parts)
{
    CHECK(st == CB_ERR_INVALID && check_msg_has(err->msg, parts), "%s: status %d, message \"%s\"",
          what, (int)st, err->msg);
}

#define EXPECT_INVALID(call, what, ...)                                                            \
    do {                                                                                           \
        const char *const parts_[] = {__VA_ARGS__, NULL};                                          \
        cb_error_clear(&err);                                                                      \
        expect_invalid((call), &err, what, parts_);                                                \
    } while (0)

static void test_bad_input(void)
{
    cb_error err;
    double o[3] = {1, 2, 3}, z[3] = {0, 0, 2}, x[3] = {1, 1, 0}, zero[3] = {0, 0, 0};
    double nanv[3] = {0, NAN, 1}, infv[3] = {INFINITY, 0, 0};
    double near_z[3] = {1e-17, 0, -5};
    cb_frame f, keep;
    cb_frame_make(&keep, o, z, x, NULL);
    f = keep;
    EXPECT_INVALID(cb_frame_make(&f, o, zero, x, &err), "zero axis", "axis", "zero");
    EXPECT_INVALID(cb_frame_make(&f, o, nanv, x, &err), "NaN axis", "axis", "not finite");
    EXPECT_INVALID(cb_frame_make(&f, nanv, z, x, &err), "NaN origin", "origin", "not finite");
    EXPECT_INVALID(cb_frame_make(&f, infv, z, x, &err), "inf origin", "origin", "not finite");
    EXPECT_INVALID(cb_frame_make(&f, o, z, z, &err), "ref = axis", "reference", "parallel");
    EXPECT_INVALID(cb_frame_make(&f, o, z, near_z, &err), "ref ~ -axis", "reference", "parallel");
    EXPECT_INVALID(cb_frame_make(&f, o, z, zero, &err), "zero ref", "reference", "zero");
    EXPECT_INVALID(cb_frame_make(&f, o, z, infv, &err), "inf ref", "reference", "not finite");
    CHECK(!memcmp(&f, &keep, sizeof f), "a rejected frame_make changed its output");

    cb_analytic_surface s, before;
    cb_analytic_sphere(&s, &keep, 1, NULL);
    before = s;
    const double bad_r[] = {0, -1, NAN, INFINITY};
    for (int k = 0; k < 4; k++) {
        EXPECT_INVALID(cb_analytic_cylinder(&s, &keep, bad_r[k], &err), "cylinder radius",
                       "cylinder", "radius");
        EXPECT_INVALID(cb_analytic_sphere(&s, &keep, bad_r[k], &err), "sphere radius", "sphere",
                       "radius");
        EXPECT_INVALID(cb_analytic_torus(&s, &keep, bad_r[k], 0.5, &err), "torus R", "torus",
                       "major radius");
        EXPECT_INVALID(cb_analytic_torus(&s, &keep, 2, bad_r[k], &err), "torus r", "torus",
                       "minor radius");
        EXPECT_INVALID(cb_analytic_ellipsoid(&s, &keep, bad_r[k], 1, 1, &err), "ellipsoid a",
                       "ellipsoid", "semi-axis a");
        EXPECT_INVALID(cb_analytic_ellipsoid(&s, &keep, 1, bad_r[k], 1, &err), "ellipsoid b",
                       "ellipsoid", "semi-axis b");
        EXPECT_INVALID(cb_analytic_ellipsoid(&s, &keep, 1, 1, bad_r[k], &err), "ellipsoid c",
                       "ellipsoid", "semi-axis c");
        if (k > 0) /* the cone takes radius 0 */
            EXPECT_INVALID(cb_analytic_cone(&s, &keep, bad_r[k], 0.5, &err), "cone radius", "cone",
                           "radius");
    }
    const double bad_angle[] = {0, pi / 2, -0.3, 2, NAN};
    for (int k = 0; k < 5; k++)
        EXPECT_INVALID(cb_analytic_cone(&s, &keep, 1, bad_angle[k], &err), "cone angle", "cone",
                       "semi-angle");
    EXPECT_INVALID(cb_analytic_torus(&s, &keep, 1, 1, &err), "horn torus", "torus",
                   "horn torus", "not supported");
    CHECK(!memcmp(&s, &before, sizeof s), "a rejected constructor changed its output");
    CHECK(cb_analytic_torus(&s, &keep, 1, 2, &err) == CB_OK, "spindle torus: %s", err.msg);
    CHECK(cb_analytic_cone(&s, &keep, 0, 0.5, &err) == CB_OK, "cone with apex at the origin: %s",
          err.msg);

    /* Ranges. */
    cb_analytic_surface pl, cy, co, sp, to, el;
    cb_analytic_plane(&pl, &keep, NULL);
    cb_analytic_cylinder(&cy, &keep, 1, NULL);
    cb_analytic_cone(&co, &keep, 1, pi / 4, NULL); /* apex at v = -1 */
    cb_analytic_sphere(&sp, &keep, 1, NULL);
    cb_analytic_torus(&to, &keep, 2, 1, NULL);
    cb_analytic_ellipsoid(&el, &keep, 1, 2, 3, NULL);
    cb_nurbs_surface_t N;
    cb_nurbs_surface_init(N);
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &cy, 1, 1, 0, 1, &err), "empty u", "cylinder", "u range",
                   "empty");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &pl, 0, 1, 2, 1, &err), "reversed v", "plane", "v range",
                   "empty");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &sp, 0, NAN, 0, 1, &err), "NaN u", "sphere", "u range",
                   "not finite");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &to, 0, 1, 0, INFINITY, &err), "inf v", "torus",
                   "v range", "not finite");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &cy, 0, 2 * pi + 1e-9, 0, 1, &err), "u > 2 pi",
                   "cylinder", "u range", "more than 2 pi");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &to, 0, 1, -1, 6, &err), "torus v > 2 pi", "torus",
                   "v range", "more than 2 pi");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &sp, 0, 1, -1.6, 0, &err), "sphere v < -pi/2", "sphere",
                   "v range", "[-pi/2, pi/2]");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &el, 0, 1, 0, 1.6, &err), "ellipsoid v > pi/2",
                   "ellipsoid", "v range", "[-pi/2, pi/2]");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &co, 0, 1, -2, 0, &err), "cone across the apex", "cone",
                   "crosses the apex");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &sp, 0, 1, nextafter(-pi / 2, -2), 0, &err),
                   "sphere v an ulp below -pi/2", "sphere", "v range", "[-pi/2, pi/2]");
    EXPECT_INVALID(cb_analytic_to_nurbs(N, &co, 0, 1, nextafter(-1 / tan(pi / 4), -2), 0, &err),
                   "cone an ulp across the apex", "cone", "crosses the apex");
    CHECK(N->cw == NULL && N->n_u == 0, "a rejected to_nurbs changed its output");
    /* Boundary cases that must pass: a full turn from any start, the whole sphere, a cone
     * patch ending at its apex, the plane's u longer than 2 pi. */
    for (int k = 0; k < 100; k++) {
        double u0 = -7 + 0.1373 * k;
        CHECK(cb_analytic_to_nurbs(N, &to, u0, u0 + 2 * pi, u0, u0 + 2 * pi, &err) == CB_OK,
              "full turn from %.17g rejected: %s", u0, err.msg);
    }
    CHECK(cb_analytic_to_nurbs(N, &sp, -pi, pi, -pi / 2, pi / 2, &err) == CB_OK, "%s", err.msg);
    CHECK(cb_analytic_to_nurbs(N, &co, 0, 1, -1 / tan(pi / 4), 0, &err) == CB_OK, "%s", err.msg);
    CHECK(cb_analytic_to_nurbs(N, &co, 0, 1, -3, -1 / tan(pi / 4), &err) == CB_OK, "%s", err.msg);
    CHECK(cb_analytic_to_nurbs(N, &pl, -10, 10, 0, 1, &err) == CB_OK, "%s", err.msg);
    cb_nurbs_surface_clear(N);

    /* Arcs. */
    cb_nurbs_curve_t C;
    cb_nurbs_curve_init(C);
    double xd[3] = {1, 0, 0}, yd[3] = {0, 1, 0}, xd2[3] = {-2, 0, 0};
    EXPECT_INVALID(cb_nurbs_curve_arc(C, o, xd, yd, 0, 0, 1, &err), "arc radius 0", "arc",
                   "radius");
    EXPECT_INVALID(cb_nurbs_curve_arc(C, o, xd, yd, NAN, 0, 1, &err), "arc radius NaN", "arc",
                   "radius");
    EXPECT_INVALID(cb_nurbs_curve_arc(C, o, xd, xd2, 1, 0, 1, &err), "parallel dirs", "arc",
                   "parallel");
    EXPECT_INVALID(cb_nurbs_curve_arc(C, o, zero, yd, 1, 0, 1, &err), "zero dir", "arc", "zero");
    EXPECT_INVALID(cb_nurbs_curve_arc(C, nanv, xd, yd, 1, 0, 1, &err), "NaN center", "arc",
                   "not finite");
    EXPECT_INVALID(cb_nurbs_curve_arc(C, o, xd, yd, 1, 1, 1, &err), "empty arc", "arc",
                   "angle range", "empty");
    EXPECT_INVALID(cb_nurbs_curve_arc(C, o, xd, yd, 1, 0, 7, &err), "arc > 2 pi", "arc",
                   "more than 2 pi");
    CHECK(C->cw == NULL, "a rejected arc changed its output");
    cb_nurbs_curve_clear(C);
}

/* Parabola and hyperbola arcs (cb_nurbs_curve_parabola, _hyperbola): every sample lies on
 * the conic (y^2 = 4 f x in the frame; x^2 / a^2 - y^2 / b^2 = 1 with x > 0), runs one way
 * along it, and the ends (and, for the parabola, every parameter; for the hyperbola every
 * knot) are the conic's points at the same parameter. */
static void test_open_conics(check_rng *rng)
{
    cb_nurbs_curve_t C;
    cb_nurbs_curve_init(C);
    cb_error err;
    double worst = 0;
    for (int trial = 0; trial < 200; trial++) {
        cb_frame f;
        random_frame(&f, rng, 10);
        int hyp = trial % 2;
        double p1 = check_rng_uniform(rng, 0.1, 5), p2 = check_rng_uniform(rng, 0.1, 5);
        double t0 = check_rng_uniform(rng, -4, 4), t1 = t0 + check_rng_uniform(rng, 0.01, 7);
        cb_status st = hyp ? cb_nurbs_curve_hyperbola(C, f.o, f.x, f.y, p1, p2, t0, t1, &err)
                           : cb_nurbs_curve_parabola(C, f.o, f.x, f.y, p1, t0, t1, &err);
        CHECK(st == CB_OK, "trial %d: %s [%g, %g]: %s", trial, hyp ? "hyperbola" : "parabola",
              t0, t1, err.msg);
        if (st)
            continue;
        CHECK(cb_nurbs_curve_validate(C, &err) == CB_OK, "trial %d: %s", trial, err.msg);
        double a, b;
        cb_nurbs_curve_domain(C, &a, &b);
        CHECK(a == t0 && b == t1, "trial %d: domain [%g, %g], want [%g, %g]", trial, a, b, t0, t1);
        double prev = -HUGE_VAL, scale = 10 + (hyp ? p1 * cosh(fmax(fabs(t0), fabs(t1))) : p1 * 64);
        for (int k = 0; k <= 100; k++) {
            double t = t0 + (t1 - t0) * k / 100, p[3], l[3];
            cb_nurbs_curve_eval(p, C, t);
            cb_frame_to_local(l, &f, p);
            double resid, along;
            if (hyp) {
                double X = l[0] * l[0] / (p1 * p1), Y = l[1] * l[1] / (p2 * p2);
                resid = fabs(X - Y - 1) / (X + Y) + (l[0] > 0 ? 0 : 1);
                along = asinh(l[1] / p2);
            } else {
                resid = fabs(l[1] * l[1] - 4 * p1 * l[0]) / (p1 * p1 + l[1] * l[1]);
                along = l[1] / (2 * p1);
                /* polynomial: the parameter is t itself */
                resid = fmax(resid, fabs(along - t) / (1 + fabs(t)));
            }
            resid = fmax(resid, fabs(l[2]) / scale);
            worst = fmax(worst, resid);
            CHECK(resid < 1e-12 && along > prev - 1e-12, "trial %d t %g: off the %s by %g", trial,
                  t, hyp ? "hyperbola" : "parabola", resid);
            prev = along;
        }
        for (int k = C->deg; k <= C->n; k++) {
            double t = C->knots[k], p[3], l[3];
            cb_nurbs_curve_eval(p, C, t);
            cb_frame_to_local(l, &f, p);
            double want = hyp ? p2 * sinh(t) : 2 * p1 * t;
            CHECK(fabs(l[1] - want) <= 1e-12 * (1 + fabs(want)), "trial %d: at knot %g y %g, want %g",
                  trial, t, l[1], want);
        }
    }
    double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0};
    CHECK(cb_nurbs_curve_parabola(C, o, x, y, 0, 0, 1, &err) == CB_ERR_INVALID,
          "parabola of focal distance 0 accepted");
    CHECK(cb_nurbs_curve_hyperbola(C, o, x, y, 1, 1, 1, 1, &err) == CB_ERR_INVALID,
          "empty hyperbola range accepted");
    CHECK(cb_nurbs_curve_hyperbola(C, o, x, x, 1, 1, 0, 1, &err) == CB_ERR_INVALID,
          "hyperbola with parallel axes accepted");
    printf("parabola and hyperbola arcs: largest residual %.2g\n", worst);
    cb_nurbs_curve_clear(C);
}

int main(void)
{
    check_rng rng = {20240611};
    test_frames(&rng);
    test_poly3(&rng);
    test_implicit(&rng);
    test_derivs(&rng);
    test_to_nurbs(&rng);
    test_arcs(&rng);
    test_open_conics(&rng);
    test_bad_input();
    printf("max: frame %.2g, eval F %.2g (world: %.2g of terms, %.2g scaled), nurbs F %.2g, nurbs "
           "distance %.2g, corners %.2g, "
           "knots %.2g, arc %.2g (radius %.2g), derivatives %.2g\n",
           max_frame_err, max_eval_resid, max_world_back, max_world_fwd, max_nurbs_resid,
           max_nurbs_shape, max_corner_dev, max_knot_dev, max_arc_resid, max_arc_radius,
           max_deriv_err);
    return check_report("analytic");
}
