/* ssi_recog.c — B-spline surfaces that lie on a plane, a cylinder, a sphere or a cone, proved
 * so, and the pairs of faces they make taken by the analytic closed forms (see
 * _cb_ssi_recognised_pair).
 *
 * CAD systems write analytic faces as B-splines (Open CASCADE's NurbsConvert, exporters that
 * write everything as B_SPLINE_SURFACE): periodic nets of 120 degree arcs, quarter arcs with
 * rounded weights, any knot vector and parameterisation. The B-spline routes certify the
 * transversal pairs of such faces, but not the tangencies and the crossing nodes of the
 * analytic geometry (a Steinmetz pair, a plug in its hole, a sphere in a cylinder), which the
 * rounded nets turn into near-misses. The closed forms decide those.
 *
 * Method: a candidate surface is fitted to points and normals sampled on the B-spline (least
 * squares; the samples only propose it). It is accepted when the whole B-spline is PROVED to lie
 * within delta of it: per Bezier patch, the candidate's implicit equation composed with the
 * patch in homogeneous local coordinates is a polynomial whose Bernstein coefficients bound it
 * (products computed with a round-off bound, cb_bernstein_mul_2d), and the distance follows
 * from the equation's factorisation (plane: |z'|; cylinder, sphere: |F| / r; cone: |F| cos a /
 * (rho + z' tan a)), with the rounding of the local coordinates and of the Bezier extraction
 * added. Nothing is decided by the samples. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "ssi/ssi.h"
#include "ssi/ssi_tol.h"

/* Samples per direction over the B-spline's domain for fitting a candidate. */
#define FIT_GRID 9
#define FIT_N (FIT_GRID * FIT_GRID)

/* A fitted candidate is tried for the proof only when every sample is within this fraction of
 * the samples' size of it (it saves the proof's cost on surfaces that are not of the kind). */
#define FIT_REL 1e-7

static void sub3(double d[3], const double a[3], const double b[3])
{
    for (int k = 0; k < 3; k++)
        d[k] = a[k] - b[k];
}

typedef struct {
    int n;
    double X[FIT_N][3], N[FIT_N][3];
    double m[3]; /* centroid */
    double size; /* diagonal of the samples' box */
} samples;

/* Points and unit normals at the centres of a FIT_GRID x FIT_GRID grid of the domain (cell
 * centres: never on a pole or a degenerate side). 0 when fewer than half have a normal. */
static int take_samples(samples *S, const cb_nurbs_surface_struct *s)
{
    double d[4], lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    cb_nurbs_surface_domain(s, d);
    S->n = 0;
    memset(S->m, 0, sizeof S->m);
    for (int i = 0; i < FIT_GRID; i++)
        for (int j = 0; j < FIT_GRID; j++) {
            double u = d[0] + (d[1] - d[0]) * (i + 0.5) / FIT_GRID;
            double v = d[2] + (d[3] - d[2]) * (j + 0.5) / FIT_GRID, D[6][3], n[3];
            cb_nurbs_surface_eval_derivs(D, s, u, v);
            cb_vec3_cross(n, D[1], D[2]);
            double len = cb_vec3_norm(n);
            if (!(len > 0) || !isfinite(len))
                continue;
            for (int k = 0; k < 3; k++) {
                S->X[S->n][k] = D[0][k];
                S->N[S->n][k] = n[k] / len;
                S->m[k] += D[0][k];
                lo[k] = fmin(lo[k], D[0][k]);
                hi[k] = fmax(hi[k], D[0][k]);
            }
            S->n++;
        }
    if (S->n < FIT_N / 2)
        return 0;
    for (int k = 0; k < 3; k++)
        S->m[k] /= S->n;
    double e[3];
    sub3(e, hi, lo);
    S->size = cb_vec3_norm(e);
    return S->size > 0;
}

/* Largest distance of the samples from a (closed forms of the analytic inversion). */
static double sample_dev(const samples *S, const cb_analytic_surface *a)
{
    double worst = 0;
    for (int i = 0; i < S->n; i++) {
        double uv[2], P[3];
        _cb_ssi_analytic_invert(uv, a, S->X[i]);
        cb_analytic_eval(P, a, uv[0], uv[1]);
        worst = fmax(worst, cb_vec3_dist(P, S->X[i]));
    }
    return worst;
}

static int fit_plane(cb_analytic_surface *a, const samples *S)
{
    double z[3] = {0, 0, 0};
    for (int i = 0; i < S->n; i++)
        for (int k = 0; k < 3; k++)
            z[k] += S->N[i][k];
    if (!(cb_vec3_normalize(z) > 0))
        return 0;
    cb_frame f;
    return cb_frame_make(&f, S->m, z, NULL, NULL) == CB_OK &&
           cb_analytic_plane(a, &f, NULL) == CB_OK;
}

/* |X - m|^2 = 2 c . (X - m) + k in the least squares sense: centre m + c, radius^2 k + |c|^2. */
static int fit_sphere(cb_analytic_surface *a, const samples *S)
{
    double A[16] = {0}, b[4] = {0};
    for (int i = 0; i < S->n; i++) {
        double q[3], row[4];
        sub3(q, S->X[i], S->m);
        double rhs = cb_vec3_dot(q, q);
        for (int k = 0; k < 3; k++)
            row[k] = 2 * q[k] / S->size;
        row[3] = 1;
        for (int r = 0; r < 4; r++) {
            b[r] += row[r] * rhs;
            for (int c = 0; c < 4; c++)
                A[4 * r + c] += row[r] * row[c];
        }
    }
    if (!cb_linsolve(A, b, 4, 0))
        return 0;
    double c[3] = {b[0] / S->size, b[1] / S->size, b[2] / S->size};
    double r2 = b[3] + cb_vec3_dot(c, c), o[3];
    if (!(r2 > 0) || !(sqrt(r2) < 1e6 * S->size))
        return 0;
    for (int k = 0; k < 3; k++)
        o[k] = S->m[k] + c[k];
    cb_frame f;
    double z[3] = {0, 0, 1};
    return cb_frame_make(&f, o, z, NULL, NULL) == CB_OK &&
           cb_analytic_sphere(a, &f, sqrt(r2), NULL) == CB_OK;
}

/* The axis: the direction the normals are perpendicular to (least eigenvector of sum n n^T);
 * then a circle fitted to the points projected across it. */
static int fit_cylinder(cb_analytic_surface *a, const samples *S)
{
    double M[3][3] = {{0}}, V[3][3];
    for (int i = 0; i < S->n; i++)
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                M[r][c] += S->N[i][r] * S->N[i][c];
    cb_sym3_eigen(V, M);
    int best = 0;
    for (int k = 1; k < 3; k++)
        if (M[k][k] < M[best][best])
            best = k;
    double z[3] = {V[best][0], V[best][1], V[best][2]};
    if (!(cb_vec3_normalize(z) > 0))
        return 0;
    for (int i = 0; i < S->n; i++)
        if (!(fabs(cb_vec3_dot(S->N[i], z)) <= 1e-6))
            return 0;
    cb_frame f0;
    if (cb_frame_make(&f0, S->m, z, NULL, NULL) != CB_OK)
        return 0;
    double A[9] = {0}, b[3] = {0};
    for (int i = 0; i < S->n; i++) {
        double l[3];
        cb_frame_to_local(l, &f0, S->X[i]);
        double row[3] = {2 * l[0] / S->size, 2 * l[1] / S->size, 1},
               rhs = l[0] * l[0] + l[1] * l[1];
        for (int r = 0; r < 3; r++) {
            b[r] += row[r] * rhs;
            for (int c = 0; c < 3; c++)
                A[3 * r + c] += row[r] * row[c];
        }
    }
    if (!cb_linsolve(A, b, 3, 0))
        return 0;
    double cl[3] = {b[0] / S->size, b[1] / S->size, 0}, o[3];
    double r2 = b[2] + cl[0] * cl[0] + cl[1] * cl[1];
    if (!(r2 > 0) || !(sqrt(r2) < 1e6 * S->size))
        return 0;
    cb_frame_to_world(o, &f0, cl);
    cb_frame f;
    return cb_frame_make(&f, o, z, NULL, NULL) == CB_OK &&
           cb_analytic_cylinder(a, &f, sqrt(r2), NULL) == CB_OK;
}

/* The unit normals of a cone make one angle with its axis: the axis is the least eigenvector of
 * their covariance, sin(semi-angle) = |n . axis|. The apex lies on every tangent plane: least
 * squares of n . (apex - X) = 0. The frame's origin is the apex (radius 0), its z towards the
 * samples. */
static int fit_cone(cb_analytic_surface *a, const samples *S)
{
    double nb[3] = {0, 0, 0}, C[3][3] = {{0}}, V[3][3], A[9] = {0}, b[3] = {0};
    for (int i = 0; i < S->n; i++)
        for (int k = 0; k < 3; k++)
            nb[k] += S->N[i][k] / S->n;
    for (int i = 0; i < S->n; i++) {
        double d[3], nx = cb_vec3_dot(S->N[i], S->X[i]);
        sub3(d, S->N[i], nb);
        for (int r = 0; r < 3; r++) {
            b[r] += S->N[i][r] * nx;
            for (int c = 0; c < 3; c++) {
                C[r][c] += d[r] * d[c];
                A[3 * r + c] += S->N[i][r] * S->N[i][c];
            }
        }
    }
    cb_sym3_eigen(V, C);
    int best = 0;
    for (int k = 1; k < 3; k++)
        if (C[k][k] < C[best][best])
            best = k;
    double z[3] = {V[best][0], V[best][1], V[best][2]};
    if (!(cb_vec3_normalize(z) > 0))
        return 0;
    double s = cb_vec3_dot(nb, z);
    if (!(fabs(s) > 1e-6 && fabs(s) < 1 - 1e-6))
        return 0;
    if (!cb_linsolve(A, b, 3, 0))
        return 0;
    double side = 0;
    for (int i = 0; i < S->n; i++) {
        double q[3];
        sub3(q, S->X[i], b);
        side += cb_vec3_dot(q, z);
    }
    if (side < 0)
        for (int k = 0; k < 3; k++)
            z[k] = -z[k];
    cb_frame f;
    return cb_frame_make(&f, b, z, NULL, NULL) == CB_OK &&
           cb_analytic_cone(a, &f, 0, asin(fabs(s)), NULL) == CB_OK;
}

/* ---------------------------------------------------------------- the proof ---------------- */

/* A bound on the distance from the rational Bezier patch pat to the surface a (over the whole
 * patch), or HUGE_VAL when this method gives none (a cone patch reaching its apex). The patch is
 * written in a's local frame in homogeneous form (X, Y, Z, W), a's equation composed with it in
 * Bernstein form, and the distance read from the equation's factorisation (see the file's
 * head); round-off of the local coordinates, of the products and of the Bezier extraction is
 * added. -1 when out of memory. */
static double patch_dist(const cb_nurbs_surface_struct *pat, const cb_analytic_surface *a)
{
    const double u = ldexp(1.0, -53);
    int p = pat->deg_u, q = pat->deg_v, n = (p + 1) * (q + 1), n2 = (2 * p + 1) * (2 * q + 1);
    const cb_frame *f = &a->frame;
    double *L = malloc((size_t)(4 * n + 4 * n2) * sizeof(double));
    if (!L)
        return -1;
    double *X = L, *Y = L + n, *Z = L + 2 * n, *W = L + 3 * n, *G = L + 4 * n, *E = G + n2,
           *T = E + n2, *B = T + n2;
    double wmin = HUGE_VAL, eps = 0, onorm = fabs(f->o[0]) + fabs(f->o[1]) + fabs(f->o[2]);
    double cwmax = 0, zmin = HUGE_VAL;
    for (int k = 0; k < n; k++) {
        const double *cw = pat->cw + 4 * k;
        double w = cw[3], d[3];
        if (!(w > 0)) {
            free(L);
            return HUGE_VAL;
        }
        for (int c = 0; c < 3; c++)
            d[c] = cw[c] - f->o[c] * w;
        X[k] = cb_vec3_dot(f->x, d);
        Y[k] = cb_vec3_dot(f->y, d);
        Z[k] = cb_vec3_dot(f->z, d);
        W[k] = w;
        wmin = fmin(wmin, w);
        zmin = fmin(zmin, Z[k] / w);
        double mag = fabs(cw[0]) + fabs(cw[1]) + fabs(cw[2]) + onorm * w;
        /* each local coordinate: 2 roundings in d, 5 in the dot product, on terms of size mag */
        eps = fmax(eps, 8 * u * mag / w);
        cwmax = fmax(cwmax, mag / w);
    }
    /* Extraction by knot insertion: convex combinations of the net, a few roundings per
     * level, at most p + q levels. */
    eps = sqrt(3.0) * eps + 4 * (p + q + 2) * u * cwmax;
    double bound = 0;
    if (a->kind == CB_ANALYTIC_PLANE) {
        for (int k = 0; k < n; k++)
            bound = fmax(bound, fabs(Z[k]) / W[k]);
        free(L);
        return bound + eps;
    }
    /* G = X^2 + Y^2 (+ Z^2 for a sphere) - r^2 W^2 (cylinder, sphere) or - tan^2 a Z^2 (cone),
     * with E its round-off bound. */
    double c_w = a->kind == CB_ANALYTIC_CONE ? 0 : a->r1 * a->r1, ta = tan(a->angle);
    double c_z = a->kind == CB_ANALYTIC_SPHERE ? 1 : (a->kind == CB_ANALYTIC_CONE ? -ta * ta : 0);
    cb_bernstein_mul_2d(G, E, X, X, p, q, p, q);
    const double *fac[3] = {Y, Z, W};
    const double coef[3] = {1, c_z, -c_w};
    for (int t = 0; t < 3; t++) {
        if (coef[t] == 0)
            continue;
        cb_bernstein_mul_2d(T, B, fac[t], fac[t], p, q, p, q);
        for (int k = 0; k < n2; k++) {
            double add = coef[t] * T[k];
            E[k] += fabs(coef[t]) * B[k] + 2 * u * (fabs(G[k]) + fabs(add));
            G[k] += add;
        }
    }
    double gmax = 0;
    for (int k = 0; k < n2; k++)
        gmax = fmax(gmax, fabs(G[k]) + E[k]);
    free(L);
    /* |F| <= gmax / W^2 with F the equation at the Euclidean point. */
    double fmax_ = gmax / (wmin * wmin) * (1 + 4 * u);
    if (a->kind == CB_ANALYTIC_CONE) {
        if (!(zmin > 0))
            return HUGE_VAL;
        bound = fmax_ * cos(a->angle) / (ta * zmin);
    } else {
        bound = fmax_ / a->r1;
    }
    return bound * (1 + 8 * u) + eps;
}

/* The same B-spline exactly: degrees, counts, knots and homogeneous control points. */
static int identical(const cb_nurbs_surface_struct *a, const cb_nurbs_surface_struct *b)
{
    if (a->deg_u != b->deg_u || a->deg_v != b->deg_v || a->n_u != b->n_u || a->n_v != b->n_v)
        return 0;
    for (int k = 0; k < a->n_u + a->deg_u + 1; k++)
        if (a->knots_u[k] != b->knots_u[k])
            return 0;
    for (int k = 0; k < a->n_v + a->deg_v + 1; k++)
        if (a->knots_v[k] != b->knots_v[k])
            return 0;
    for (int k = 0; k < 4 * a->n_u * a->n_v; k++)
        if (a->cw[k] != b->cw[k])
            return 0;
    return 1;
}

/* The proved largest distance of s from a (<= delta: 1 and *dev set), or 0. */
static int prove_on(double *dev, const cb_nurbs_surface_struct *s, const cb_analytic_surface *a,
                    double delta)
{
    cb_nurbs_surface_struct *pat = NULL;
    int npu = 0, npv = 0;
    cb_error err;
    if (cb_nurbs_surface_extract_bezier(&pat, &npu, &npv, s, &err) != CB_OK)
        return 0;
    double worst = 0;
    for (int k = 0; k < npu * npv && worst <= delta; k++) {
        double d = patch_dist(pat + k, a);
        worst = d < 0 ? HUGE_VAL : fmax(worst, d);
    }
    cb_nurbs_surface_array_free(pat, npu * npv);
    *dev = worst;
    return worst <= delta;
}

/* An analytic range holding s's image: angular directions whole turns (latitudes all), linear
 * ones the span of s's Euclidean control points in that coordinate (the surface lies in their
 * hull: positive weights), grown by delta. */
static void image_range(double range[4], const cb_analytic_surface *a,
                        const cb_nurbs_surface_struct *s, double delta)
{
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int k = 0; k < s->n_u * s->n_v; k++) {
        const double *cw = s->cw + 4 * k;
        double X[3] = {cw[0] / cw[3], cw[1] / cw[3], cw[2] / cw[3]}, l[3];
        cb_frame_to_local(l, &a->frame, X);
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], l[c]);
            hi[c] = fmax(hi[c], l[c]);
        }
    }
    if (a->kind == CB_ANALYTIC_PLANE) {
        range[0] = lo[0] - delta;
        range[1] = hi[0] + delta;
        range[2] = lo[1] - delta;
        range[3] = hi[1] + delta;
        return;
    }
    range[0] = -CB_SSI_PI;
    range[1] = CB_SSI_PI;
    if (a->kind == CB_ANALYTIC_SPHERE) {
        range[2] = -CB_SSI_PI / 2;
        range[3] = CB_SSI_PI / 2;
    } else {
        range[2] = lo[2] - delta;
        range[3] = hi[2] + delta;
    }
}

int _cb_ssi_recognise(cb_analytic_surface *a, double range[4], double *dev,
                      const cb_nurbs_surface_struct *s, double delta)
{
    samples *S = malloc(sizeof *S);
    if (!S)
        return 0;
    int ok = 0;
    if (take_samples(S, s)) {
        int (*fit[4])(cb_analytic_surface *, const samples *) = {fit_plane, fit_cylinder,
                                                                   fit_sphere, fit_cone};
        for (int k = 0; k < 4 && !ok; k++) {
            cb_analytic_surface c;
            if (!fit[k](&c, S) || !(sample_dev(S, &c) <= FIT_REL * S->size))
                continue;
            if (prove_on(dev, s, &c, delta)) {
                *a = c;
                image_range(range, a, s, delta);
                ok = 1;
            }
        }
    }
    free(S);
    return ok;
}

/* ---------------------------------------------------------------- pairs -------------------- */

/* The closed forms' coincidences are between the analytic surfaces; the B-splines lie within
 * dev of them, so a coincidence is exact for the B-splines only when both are the same net or
 * lie on their analytic surfaces exactly (dev 0). Otherwise it is within tolerance, its width
 * the analytic one plus both deviations, with a COINCIDENCE region in the B-splines' domains.
 * CB_ERR_NOMEM. */
static cb_status demote_coincidences(cb_ssi_result_t t, const cb_ssi_surface *const in[2],
                                     const int rec[2], const double dev[2])
{
    int same = in[0]->kind == CB_SSI_NURBS && in[1]->kind == CB_SSI_NURBS &&
               identical(in[0]->nurbs, in[1]->nurbs);
    for (slong g = 0; g < t->n_regions; g++) {
        cb_ssi_region *rg = t->region + g;
        if (rg->kind != CB_SSI_REGION_COINCIDENCE)
            continue;
        rg->width += dev[0] + dev[1];
        for (int q = 0; q < 2; q++)
            if (rec[q])
                cb_nurbs_surface_domain(in[q]->nurbs, q ? rg->box_b : rg->box_a);
    }
    for (slong k = 0; k < t->n_coincident; k++) {
        cb_ssi_coincident *c = t->coincident + k;
        if (!c->exact) {
            c->width += dev[0] + dev[1];
            continue;
        }
        if (same || (dev[0] == 0 && dev[1] == 0))
            continue;
        c->exact = 0;
        c->width = dev[0] + dev[1];
        t->pairs_certified--;
        t->pairs_within_tolerance++;
        cb_ssi_region *g = _cb_ssi_add_region(t, CB_SSI_REGION_COINCIDENCE, c->face_a,
                                              c->face_b, -1, -1, c->width);
        if (!g)
            return CB_ERR_NOMEM;
        for (int q = 0; q < 3; q++) {
            g->lo[q] = -HUGE_VAL;
            g->hi[q] = HUGE_VAL;
        }
        for (int q = 0; q < 2; q++) {
            double *bx = q ? g->box_b : g->box_a;
            if (in[q]->kind == CB_SSI_NURBS) {
                cb_nurbs_surface_domain(in[q]->nurbs, bx);
                cb_aabb b;
                cb_nurbs_surface_aabb(&b, in[q]->nurbs);
                for (int d = 0; d < 3; d++) {
                    g->lo[d] = fmax(g->lo[d], b.lo[d]);
                    g->hi[d] = fmin(g->hi[d], b.hi[d]);
                }
            } else {
                memcpy(bx, in[q]->range, 4 * sizeof(double));
            }
        }
    }
    return CB_OK;
}

cb_status _cb_ssi_recognised_pair(cb_ssi_result_t r, const cb_ssi_surface *A,
                                  const cb_ssi_surface *B, int face_a, int face_b,
                                  const cb_ssi_opts *opts, int *done, cb_error *err)
{
    *done = 0;
    const cb_ssi_surface *in[2] = {A, B};
    cb_ssi_surface S[2];
    int rec[2] = {0, 0};
    double dev[2] = {0, 0};
    cb_topo_surface ts[2];
    cb_topo_inverter inv[2];
    const _cb_ssi_image *img[2] = {NULL, NULL};
    _cb_ssi_image im[2];
    cb_status st = CB_OK;
    for (int k = 0; k < 2; k++)
        cb_topo_surface_init(ts + k);
    for (int k = 0; k < 2 && st == CB_OK; k++) {
        S[k] = *in[k];
        if (in[k]->kind != CB_SSI_NURBS)
            continue;
        const cb_nurbs_surface_struct *n = in[k]->nurbs;
        /* Proved within a thousandth of the tolerance (the default tolerance relative to the
         * net's own size when none is given). */
        double delta = CB_SSI_RECOGNISE * opts->tol;
        if (!(opts->tol > 0)) {
            cb_aabb b;
            cb_nurbs_surface_aabb(&b, n);
            double d[3];
            sub3(d, b.hi, b.lo);
            delta = 1e-9 * cb_vec3_norm(d);
        }
        cb_analytic_surface a;
        double range[4];
        if (!_cb_ssi_recognise(&a, range, dev + k, n, delta))
            break;
        cb_ssi_surface_set_analytic(S + k, &a, range);
        ts[k].kind = CB_SURFACE_NURBS;
        st = cb_nurbs_surface_set(ts[k].nurbs, n, err);
        if (st == CB_OK)
            st = cb_topo_inverter_init(inv + k, ts + k, delta, err);
        if (st != CB_OK)
            break;
        rec[k] = 1;
        im[k].inv = inv + k;
        im[k].dev = dev[k];
        img[k] = im + k;
    }
    /* Both B-spline sides must be recognised (an analytic side is as good as one). */
    int all = st == CB_OK && (rec[0] || rec[1]) &&
              (in[0]->kind != CB_SSI_NURBS || rec[0]) && (in[1]->kind != CB_SSI_NURBS || rec[1]);
    if (all) {
        cb_ssi_result_t t;
        cb_ssi_result_init(t);
        cb_error e2; /* a failure here only means: take the B-spline route */
        cb_error_clear(&e2);
        cb_status s2 = _cb_ssi_analytic_pair_img(t, S, S + 1, img, face_a, face_b, opts, &e2);
        /* Only the closed forms are taken: the general route would certify the same surfaces
         * as the B-spline route does. */
        if (s2 == CB_OK && t->pairs_closed_form > 0 && t->n_failed == 0 && t->status == CB_OK) {
            r->tol = t->tol;
            if (demote_coincidences(t, in, rec, dev) != CB_OK)
                st = cb_error_set(err, CB_ERR_NOMEM,
                                  "ssi: out of memory recording coincident surfaces");
            else if (_cb_ssi_result_move(r, t) != CB_OK)
                st = cb_error_set(err, CB_ERR_NOMEM,
                                  "ssi: out of memory collecting the closed-form result");
            else
                *done = 1;
        } else if (s2 == CB_ERR_NOMEM) {
            st = cb_error_set(err, CB_ERR_NOMEM, "%s", e2.msg);
        }
        cb_ssi_result_clear(t);
    }
    for (int k = 0; k < 2; k++) {
        if (rec[k])
            cb_topo_inverter_clear(inv + k);
        cb_topo_surface_clear(ts + k);
    }
    return st;
}
