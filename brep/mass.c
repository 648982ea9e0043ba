/* Mass properties of B-rep shells by the divergence and Green theorems (brep/mass.h). */
#include "brep/mass.h"

#include <float.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "brep/parallel.h"

/* Integrated quantities: volume, area, first moment (x, y, z), all about the reference point. */
enum { QV, QA, QX, QY, QZ, QNX, QNY, QNZ, NQ };

enum { MAX_DEPTH_INNER = 30, MAX_DEPTH_OUTER = 30 };

/* The inner integrals are computed this much more accurately than the outer ones: their
 * error is noise to the outer error estimate, which would otherwise bisect it forever. */
static const double INNER_FACTOR = 1e-2;

/* Relative noise of the integrands' values: for the inner ones the round-off of surface
 * points and derivatives, which grows with the distance of the body from the origin relative
 * to its size and, on a B-spline surface, with its degrees (INNER_NOISE times 1 + that ratio,
 * times the mean of the two degrees where above 1: a face of linkrods' degree (6, 8) surface,
 * asked for 1e-12, bisected its inner integrals 1.3 million times in 120 s without gaining a
 * digit; its values are noisy at 2e-12 to 5e-12); for the outer ones the inner integrals'
 * accuracy (OUTER_NOISE rel_tol, INNER_FACTOR with a margin). */
static const double INNER_NOISE = 1e-12, OUTER_NOISE = 5e-2;

/* Bisections allowed per integral over a piece list: a bound on the work where an integrand
 * is rougher than the quadrature expects (an edge crossing a surface's domain boundary). */
static const long MAX_BISECTIONS = 4000;
/* Bisections of all the inner integrals of one face together: a face whose inner integrals
 * keep failing to converge would otherwise take minutes; it is an error instead. Measured:
 * an ellipsoid cap's face of the Boolean corpus of primitives takes 3.1e6 (10 s), and with
 * 6e6 (about 30 s) no face of that corpus fails; the shipped models' faces take at most 8e3. */
static const long MAX_FACE_BISECTIONS = 6000000;

/* The derivative of an edge's foot point on its face takes the surface's curvature into
 * account (J^T J + H) unless that matrix's determinant falls below this fraction of the least
 * squares one (J^T J): the edge is then about as far from the surface as the surface's radius
 * of curvature, and the foot point jumps rather than moves with the edge. */
static const double FOOT_CURVATURE_MIN = 0.25;

/* Gauss-Kronrod 7-15 nodes (x >= 0) and weights; the Gauss nodes are the odd ones. */
static const double xgk[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0};
static const double wgk[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
static const double wg[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

/* An integrand: its values out and their magnitudes mag (|out| or larger: the size of the
 * terms it is made of), which scale the accuracy asked of it. */
typedef void (*vec_fn)(double out[NQ], double mag[NQ], double x, void *ctx);

/* One Kronrod (k) and Gauss (g) estimate over [a, b] (b < a integrates backwards), and the
 * Kronrod estimate of the integral of the magnitudes (l1). */
static void gk15(double k[NQ], double g[NQ], double l1[NQ], vec_fn fn, void *ctx, double a,
                 double b)
{
    double c = 0.5 * (a + b), h = 0.5 * (b - a), f[NQ], f2[NQ], m[NQ], m2[NQ];
    fn(f, m, c, ctx);
    for (int q = 0; q < NQ; q++) {
        k[q] = wgk[7] * f[q];
        g[q] = wg[3] * f[q];
        l1[q] = wgk[7] * m[q];
    }
    for (int j = 0; j < 7; j++) {
        fn(f, m, c - h * xgk[j], ctx);
        fn(f2, m2, c + h * xgk[j], ctx);
        for (int q = 0; q < NQ; q++) {
            k[q] += wgk[j] * (f[q] + f2[q]);
            l1[q] += wgk[j] * (m[q] + m2[q]);
            if (j & 1)
                g[q] += wg[j / 2] * (f[q] + f2[q]);
        }
    }
    for (int q = 0; q < NQ; q++) {
        k[q] *= h;
        g[q] *= h;
        l1[q] *= fabs(h);
    }
}

typedef struct {
    vec_fn fn;
    void *ctx;
    int max_depth;
    const cb_context *cancel; /* checked at every split when not NULL */
    int cancelled;
    double noise; /* relative accuracy of the integrand's values */
    long budget;  /* bisections left */
} adaptive;

/* Adds to res the integral over [a, b] whose estimates k, g (and of |f|, l1) are known,
 * bisecting until every component's |k - g| is within tol or within the noise of the
 * integrand's values (no bisection can do better), to a depth and a number of bisections
 * that bound the work. */
static void adapt(double res[NQ], adaptive *ad, double a, double b, const double k[NQ],
                  const double g[NQ], const double l1[NQ], const double tol[NQ], int depth)
{
    int ok = 1;
    /* The vector area is a check, not a result: it rides on the others' subdivision. */
    for (int q = 0; q < QNX; q++)
        ok &= fabs(k[q] - g[q]) <= fmax(tol[q], ad->noise * l1[q]);
    if (ok || depth >= ad->max_depth || ad->budget <= 0 || ad->cancelled) {
        for (int q = 0; q < NQ; q++)
            res[q] += k[q];
        return;
    }
    if (ad->cancel && cb_context_cancelled(ad->cancel)) {
        ad->cancelled = 1;
        return;
    }
    ad->budget--;
    double m = 0.5 * (a + b), k1[NQ], g1[NQ], k2[NQ], g2[NQ], l1a[NQ], l1b[NQ], half[NQ];
    gk15(k1, g1, l1a, ad->fn, ad->ctx, a, m);
    gk15(k2, g2, l1b, ad->fn, ad->ctx, m, b);
    for (int q = 0; q < NQ; q++)
        half[q] = 0.5 * tol[q];
    adapt(res, ad, a, m, k1, g1, l1a, half, depth + 1);
    adapt(res, ad, m, b, k2, g2, l1b, half, depth + 1);
}

/* Adds to res the integral over the pieces [x[i], x[i + 1]] (x monotone), each to its share
 * (by length) of rel times the integral of the magnitudes over the whole, plus floor_. */
static void integrate(double res[NQ], adaptive *ad, const double *x, int n, double rel,
                      const double floor_[NQ])
{
    enum { LOCAL = 64 };
    double local[LOCAL][3][NQ], l1sum[NQ] = {0};
    if (n < 2)
        return;
    /* Without room for the first estimates they are computed twice. */
    double(*est)[3][NQ] = n - 1 <= LOCAL ? local : malloc((size_t)(n - 1) * sizeof *est);
    for (int i = 0; i + 1 < n; i++) {
        double *k = est ? est[i][0] : local[0][0], *g = est ? est[i][1] : local[0][1],
               *l1 = est ? est[i][2] : local[0][2];
        gk15(k, g, l1, ad->fn, ad->ctx, x[i], x[i + 1]);
        for (int q = 0; q < NQ; q++)
            l1sum[q] += l1[q];
    }
    double len = fabs(x[n - 1] - x[0]);
    for (int i = 0; i + 1 < n; i++) {
        double tol[NQ], part = len > 0 ? fabs(x[i + 1] - x[i]) / len : 1;
        for (int q = 0; q < NQ; q++)
            tol[q] = part * (rel * l1sum[q] + floor_[q]);
        double *k = est ? est[i][0] : local[0][0], *g = est ? est[i][1] : local[0][1],
               *l1 = est ? est[i][2] : local[0][2];
        if (!est)
            gk15(k, g, l1, ad->fn, ad->ctx, x[i], x[i + 1]);
        adapt(res, ad, x[i], x[i + 1], k, g, l1, tol, 0);
    }
    if (est != local)
        free(est);
}

/* ---------------------------------------------------------------- one face ----------------- */

/* The map from a coedge's pcurve parameter s to (u, v) on the true edge. */
typedef struct {
    const cb_topo_curve *pc, *curve;
    int convention; /* the pcurve shares the edge's parameter */
    double t0, t1;  /* edge range */
    double off[2];  /* whole periods added to the pcurve's (u, v) */
} coedge_map;

typedef struct {
    const cb_topo_inverter *inv;
    int nurbs;     /* clamp (u, v) to the B-spline domain */
    int a;         /* inner direction: 0 integrates along u (loop integral of F dv) */
    double sign;   /* +1 for F dv, -1 for -G du */
    double ref;    /* inner integrals start at this value of coordinate a */
    double c[3];   /* reference point */
    double *knots; /* breakpoints in direction a (one period when periodic) */
    int n_knots;
    double *knots_o; /* and in the other direction */
    int n_knots_o;
    double period;   /* of direction a, or 0 */
    double rel_in;   /* the inner integrals' accuracy, finer than the outer's */
    double noise_in; /* relative noise of the inner integrands */
    double floor_in[NQ], floor_out[NQ];
    double y; /* the fixed coordinate of the inner integral */
    const coedge_map *cm;
    const double *seg; /* a straight joint: (u, v) from seg[0..1] to seg[2..3] */
    double *pts;       /* scratch breakpoints */
    int cap_pts;
    long inner_left; /* bisections left to the face's inner integrals (MAX_FACE_BISECTIONS) */
} face_work;

static void clamp_uv(double uv[2], const face_work *w)
{
    if (!w->nurbs)
        return;
    for (int i = 0; i < 2; i++)
        if (!(w->inv->period[i] > 0))
            uv[i] = fmin(fmax(uv[i], w->inv->box[2 * i]), w->inv->box[2 * i + 1]);
}

/* The integrands at (u, v): (S - c).N / 3, |N|, (S - c) ((S - c).N) / 4, N, N = S_u x S_v. */
static void integrands(double out[NQ], const face_work *w, double u, double v)
{
    double uv[2] = {u, v}, d[6][3], n[3], r[3];
    clamp_uv(uv, w);
    cb_topo_inverter_eval_derivs(d, w->inv, uv[0], uv[1]);
    cb_vec3_cross(n, d[1], d[2]);
    for (int i = 0; i < 3; i++)
        r[i] = d[0][i] - w->c[i];
    double rn = cb_vec3_dot(r, n);
    out[QV] = rn / 3;
    out[QA] = cb_vec3_norm(n);
    for (int i = 0; i < 3; i++) {
        out[QX + i] = 0.25 * r[i] * rn;
        out[QNX + i] = n[i];
    }
}

static void inner_fn(double out[NQ], double mag[NQ], double x, void *ctx)
{
    const face_work *w = ctx;
    if (w->a == 0)
        integrands(out, w, x, w->y);
    else
        integrands(out, w, w->y, x);
    for (int q = 0; q < NQ; q++)
        mag[q] = fabs(out[q]);
}

static int cmp_double(const void *p, const void *q)
{
    double a = *(const double *)p, b = *(const double *)q;
    return (a > b) - (a < b);
}

/* F(x, y) = integral from ref to x of the integrands along direction a at the other
 * coordinate y, split at the knots. */
static void inner(double out[NQ], face_work *w, double x, double y)
{
    for (int q = 0; q < NQ; q++)
        out[q] = 0;
    double lo = fmin(x, w->ref), hi = fmax(x, w->ref);
    if (!(hi > lo))
        return;
    int n = 0;
    w->pts[n++] = lo;
    for (int k = 0; k < w->n_knots; k++) {
        double kn = w->knots[k];
        if (w->period > 0) {
            double m0 = ceil((lo - kn) / w->period), m1 = floor((hi - kn) / w->period);
            for (double m = m0; m <= m1; m++) {
                double z = kn + m * w->period;
                if (z > lo && z < hi && n + 2 < w->cap_pts)
                    w->pts[n++] = z;
            }
        } else if (kn > lo && kn < hi && n + 2 < w->cap_pts) {
            w->pts[n++] = kn;
        }
    }
    w->pts[n++] = hi;
    if (w->period > 0)
        qsort(w->pts, (size_t)n, sizeof *w->pts, cmp_double);
    w->y = y;
    if (w->inner_left <= 0)
        return; /* the face fails (face_integrate) */
    long budget = w->inner_left < MAX_BISECTIONS ? w->inner_left : MAX_BISECTIONS;
    adaptive ad = {inner_fn, w, MAX_DEPTH_INNER, NULL, 0, w->noise_in, budget};
    double res[NQ] = {0};
    integrate(res, &ad, w->pts, n, w->rel_in, w->floor_in);
    w->inner_left -= budget - ad.budget;
    double s = x < w->ref ? -1 : 1;
    for (int q = 0; q < NQ; q++)
        out[q] = s * res[q];
}

/* Point of a pcurve and its derivative (a closed B-spline reduced into its domain, as
 * cb_topo_pcurve_eval does). */
static void pcurve_derivs(double uv[2], double duv[2], const cb_topo_curve *pc, double s)
{
    double p[3], d[3][3];
    cb_topo_pcurve_eval(p, pc, s);
    if (pc->kind == CB_CURVE_NURBS) {
        const cb_nurbs_curve_struct *n = pc->nurbs;
        double k0 = n->knots[n->deg], k1 = n->knots[n->n], len = k1 - k0;
        if (len > 0 && (s < k0 || s > k1))
            s -= len * floor((s - k0) / len);
        s = fmin(fmax(s, k0), k1);
    }
    cb_topo_curve_eval_derivs(d, pc, s);
    uv[0] = p[0];
    uv[1] = p[1];
    duv[0] = d[1][0];
    duv[1] = d[1][1];
}

/* (u, v) of the node at pcurve parameter s moved onto the edge, and d(u, v)/ds. */
static void coedge_node(double uv[2], double duv[2], const face_work *w, const coedge_map *m,
                        double s)
{
    double pduv[2], d[6][3], t = s, dts = 1;
    pcurve_derivs(uv, pduv, m->pc, s);
    uv[0] += m->off[0];
    uv[1] += m->off[1];
    clamp_uv(uv, w);
    double cd[3][3];
    if (!m->convention) {
        /* t(s) is the foot of S(pc(s)) on the edge; its derivative follows from
         * (P(s) - C(t)).C'(t) = 0. */
        cb_topo_inverter_eval_derivs(d, w->inv, uv[0], uv[1]);
        cb_topo_curve_project(&t, m->curve, d[0], m->t0, m->t1);
        cb_topo_curve_eval_derivs(cd, m->curve, t);
        double dp[3], r[3];
        for (int i = 0; i < 3; i++) {
            dp[i] = d[1][i] * pduv[0] + d[2][i] * pduv[1];
            r[i] = d[0][i] - cd[0][i];
        }
        double den = cb_vec3_dot(cd[1], cd[1]) - cb_vec3_dot(r, cd[2]);
        dts = den != 0 ? cb_vec3_dot(dp, cd[1]) / den : 0;
    } else {
        cb_topo_curve_eval_derivs(cd, m->curve, t);
    }
    /* Gauss-Newton (slightly damped for the free parameter at a pole) onto C(t). */
    double start[2] = {uv[0], uv[1]}, r0 = -1;
    for (int it = 0; it < 8; it++) {
        cb_topo_inverter_eval_derivs(d, w->inv, uv[0], uv[1]);
        double r[3] = {d[0][0] - cd[0][0], d[0][1] - cd[0][1], d[0][2] - cd[0][2]};
        double rn = cb_vec3_norm(r);
        if (r0 < 0)
            r0 = rn;
        double a00 = cb_vec3_dot(d[1], d[1]), a01 = cb_vec3_dot(d[1], d[2]),
               a11 = cb_vec3_dot(d[2], d[2]), mu = 1e-14 * (a00 + a11);
        double g0 = cb_vec3_dot(d[1], r), g1 = cb_vec3_dot(d[2], r);
        double det = (a00 + mu) * (a11 + mu) - a01 * a01;
        if (rn == 0 || !(det > 0))
            break;
        double du = -((a11 + mu) * g0 - a01 * g1) / det, dv = -((a00 + mu) * g1 - a01 * g0) / det;
        uv[0] += du;
        uv[1] += dv;
        clamp_uv(uv, w);
        if (fabs(du) + fabs(dv) <= 1e-15 * (1 + fabs(uv[0]) + fabs(uv[1])))
            break;
    }
    cb_topo_inverter_eval_derivs(d, w->inv, uv[0], uv[1]);
    double r[3] = {d[0][0] - cd[0][0], d[0][1] - cd[0][1], d[0][2] - cd[0][2]};
    if (!(cb_vec3_norm(r) <= r0 * (1 + 1e-6) + 64 * DBL_EPSILON * (cb_vec3_norm(cd[0]) + 1))) {
        /* Newton went astray (never expected for a pcurve within tolerance): keep the fit.
         * Where the edge lies off the surface (a gap within its tolerance) Newton ends as
         * far from it as the fit, up to round-off; compared without slack, the fit was kept
         * at some nodes and not at their neighbours, noise of 1e-8 in the integrand
         * (trj5_k1-al-214.stp) that the outer integrals bisected to depth 30 at every
         * node: 25 times the work. */
        uv[0] = start[0];
        uv[1] = start[1];
        cb_topo_inverter_eval_derivs(d, w->inv, uv[0], uv[1]);
    }
    /* d(u, v)/dt of the foot point itself: differentiating J^T (S - C) = 0 gives
     * (J^T J + H) d(u, v)/dt = J^T C', H_ij = (S - C).S_ij. Without H (least squares) the
     * derivative is off by about the edge's gap times the surface curvature, and the loop
     * integral, taken with it, then no longer bounds the region the nodes enclose. */
    double a00 = cb_vec3_dot(d[1], d[1]), a01 = cb_vec3_dot(d[1], d[2]),
           a11 = cb_vec3_dot(d[2], d[2]), det = a00 * a11 - a01 * a01;
    if (det > 1e-20 * (a00 + a11) * (a00 + a11)) {
        double gap[3] = {d[0][0] - cd[0][0], d[0][1] - cd[0][1], d[0][2] - cd[0][2]};
        double h00 = a00 + cb_vec3_dot(gap, d[3]), h01 = a01 + cb_vec3_dot(gap, d[4]),
               h11 = a11 + cb_vec3_dot(gap, d[5]), hdet = h00 * h11 - h01 * h01;
        if (!(h00 > 0 && hdet > FOOT_CURVATURE_MIN * det)) {
            /* The edge is as far from the surface as the surface's radius of curvature: the
             * foot point is not a smooth function of t there; the least-squares step. */
            h00 = a00;
            h01 = a01;
            h11 = a11;
            hdet = det;
        }
        double b0 = cb_vec3_dot(d[1], cd[1]), b1 = cb_vec3_dot(d[2], cd[1]);
        duv[0] = (h11 * b0 - h01 * b1) / hdet * dts;
        duv[1] = (h00 * b1 - h01 * b0) / hdet * dts;
    } else {
        duv[0] = pduv[0];
        duv[1] = pduv[1];
    }
}

/* F d(u_o)/ds, of magnitude |F| |d(u, v)/ds|: along a coedge where u_o is constant (a circle
 * of a cylinder, with F du...) the values are round-off, and asking them a relative accuracy
 * would bisect for ever. */
static void outer_fn(double out[NQ], double mag[NQ], double s, void *ctx)
{
    face_work *w = ctx;
    double uv[2], duv[2];
    coedge_node(uv, duv, w, w->cm, s);
    inner(out, w, uv[w->a], uv[1 - w->a]);
    double f = w->sign * duv[1 - w->a], speed = fabs(duv[0]) + fabs(duv[1]);
    for (int q = 0; q < NQ; q++) {
        mag[q] = fabs(out[q]) * speed;
        out[q] *= f;
    }
}

static void segment_fn(double out[NQ], double mag[NQ], double s, void *ctx)
{
    face_work *w = ctx;
    const double *g = w->seg;
    double uv[2] = {g[0] + s * (g[2] - g[0]), g[1] + s * (g[3] - g[1])};
    inner(out, w, uv[w->a], uv[1 - w->a]);
    double f = w->sign * (g[3 - w->a] - g[1 - w->a]), speed = fabs(g[2] - g[0]) + fabs(g[3] - g[1]);
    for (int q = 0; q < NQ; q++) {
        mag[q] = fabs(out[q]) * speed;
        out[q] *= f;
    }
}

/* Appends to x the parameters in (lo, hi) where coedge m crosses a knot line of the surface
 * in the outer direction (where F has a kink): sign changes of u_o - knot at 64 samples of the
 * coedge on its edge, refined by bisection. */
static int knot_crossings(double *x, int n, int cap, const face_work *w, const coedge_map *m,
                          double lo, double hi)
{
    enum { SAMPLES = 64, BISECTIONS = 60 };
    int o = 1 - w->a;
    double per = w->inv->period[o], prev_s = lo, prev = 0, uv[2], duv[2];
    for (int i = 0; i <= SAMPLES; i++) {
        double s = lo + (hi - lo) * i / SAMPLES;
        coedge_node(uv, duv, w, m, s);
        double cur = uv[o];
        if (i > 0)
            for (int k = 0; k < w->n_knots_o; k++) {
                double kn = w->knots_o[k], a = fmin(prev, cur), b = fmax(prev, cur);
                if (per > 0)
                    kn += per * ceil((a - kn) / per);
                for (; kn < b && n + 1 < cap; kn += per > 0 ? per : HUGE_VAL) {
                    if (!(kn > a))
                        continue;
                    double s0 = prev_s, s1 = s, f0 = prev - kn;
                    for (int it = 0; it < BISECTIONS && s1 - s0 > 0; it++) {
                        double sm = 0.5 * (s0 + s1);
                        coedge_node(uv, duv, w, m, sm);
                        if ((uv[o] - kn > 0) == (f0 > 0))
                            s0 = sm;
                        else
                            s1 = sm;
                    }
                    double z = 0.5 * (s0 + s1);
                    if (z > lo && z < hi)
                        x[n++] = z;
                }
            }
        prev_s = s;
        prev = cur;
    }
    return n;
}

/* Breakpoints of the outer integral over [s0, s1]: interior knots of the pcurve and, when it
 * shares the edge's parameter, of the edge curve, and the knot line crossings. Returns the
 * count written to x. */
static int outer_breaks(double *x, int cap, const face_work *w, const coedge_map *m, double s0,
                        double s1)
{
    int n = 0;
    double lo = fmin(s0, s1), hi = fmax(s0, s1);
    x[n++] = lo;
    const cb_topo_curve *cs[2] = {m->pc, m->convention ? m->curve : NULL};
    for (int j = 0; j < 2; j++) {
        if (!cs[j] || cs[j]->kind != CB_CURVE_NURBS)
            continue;
        const cb_nurbs_curve_struct *nc = cs[j]->nurbs;
        for (int k = nc->deg + 1; k < nc->n; k++)
            if (nc->knots[k] > lo && nc->knots[k] < hi && n + 2 < cap)
                x[n++] = nc->knots[k];
    }
    n = knot_crossings(x, n, cap - 1, w, m, lo, hi);
    x[n++] = hi;
    qsort(x, (size_t)n, sizeof *x, cmp_double);
    int m_ = 1;
    for (int i = 1; i < n; i++)
        if (x[i] > x[m_ - 1])
            x[m_++] = x[i];
    n = m_;
    if (s1 < s0)
        for (int i = 0; i < n / 2; i++) {
            double t = x[i];
            x[i] = x[n - 1 - i];
            x[n - 1 - i] = t;
        }
    return n;
}

typedef struct {
    coedge_map map;
    double s0, s1;
    double start[2], end[2];
} coedge_info;

/* Whether coedge c's pcurve follows the convention: range = the edge's, mid point on it. */
static int follows_convention(const cb_topo_body *b, int c, const cb_topo_inverter *inv, double s0,
                              double s1, double tol)
{
    const cb_topo_edge *e = &b->edges[b->coedges[c].edge];
    double len = e->t1 - e->t0, lo = fmin(s0, s1), hi = fmax(s0, s1);
    if (!(fabs(lo - e->t0) <= 1e-9 * len && fabs(hi - e->t1) <= 1e-9 * len))
        return 0;
    double tm = 0.5 * (e->t0 + e->t1), uv[3], p[3], q[3];
    cb_topo_pcurve_eval(uv, &b->pcurves[b->coedges[c].pcurve], tm);
    cb_topo_inverter_eval(p, inv, uv[0], uv[1]);
    cb_topo_curve_eval(q, &b->curves[e->curve], tm);
    return cb_vec3_dist(p, q) <= 10 * tol;
}

/* Knots of the surface in direction a: B-spline knots, or a profile's for revolutions
 * (direction v) and extrusions (direction u). */
static int surface_knots(double *x, int cap, const cb_topo_surface *s, int a)
{
    const double *k = NULL;
    int n = 0;
    if (s->kind == CB_SURFACE_NURBS) {
        k = a ? s->nurbs->knots_v : s->nurbs->knots_u;
        n = (a ? s->nurbs->n_v + s->nurbs->deg_v : s->nurbs->n_u + s->nurbs->deg_u) + 1;
    } else if ((s->kind == CB_SURFACE_REVOLUTION && a == 1) ||
               (s->kind == CB_SURFACE_EXTRUSION && a == 0)) {
        if (s->profile.kind == CB_CURVE_NURBS) {
            k = s->profile.nurbs->knots;
            n = s->profile.nurbs->n + s->profile.nurbs->deg + 1;
        }
    }
    int m = 0;
    for (int i = 0; i < n && m < cap; i++)
        if (m == 0 || k[i] > x[m - 1])
            x[m++] = k[i];
    return m;
}

/* The pole on side `side` (+1: above, -1: below) of coordinate a beyond the loops' range
 * [lo, hi]: a line of the surface collapsing to a point. Returns 0 when there is none. */
static int find_pole(double *pole, const face_work *w, const cb_topo_surface *s, int side,
                     double lo, double hi, double tol)
{
    const cb_topo_inverter *inv = w->inv;
    double cand[4];
    int n = 0;
    if (s->kind == CB_SURFACE_ANALYTIC && w->a == 1) {
        const cb_analytic_surface *an = &s->analytic;
        if (an->kind == CB_ANALYTIC_SPHERE || an->kind == CB_ANALYTIC_ELLIPSOID) {
            double pi = 3.14159265358979323846, base = side > 0 ? 0.5 * pi : -0.5 * pi;
            double ref = side > 0 ? hi : lo;
            double k = side > 0 ? ceil((ref - base) / (2 * pi) - 1e-12)
                                : floor((ref - base) / (2 * pi) + 1e-12);
            cand[n++] = base + 2 * pi * k;
        } else if (an->kind == CB_ANALYTIC_CONE) {
            cand[n++] = -an->r1 / tan(an->angle);
        }
    }
    double bx = side > 0 ? inv->box[2 * w->a + 1] : inv->box[2 * w->a];
    if (isfinite(bx))
        cand[n++] = bx;
    int o = 1 - w->a;
    double per = inv->period[o];
    for (int i = 0; i < n; i++) {
        double x = cand[i];
        if (side > 0 ? x < hi - 1e-9 * (1 + fabs(hi)) : x > lo + 1e-9 * (1 + fabs(lo)))
            continue;
        double p[2], q[2];
        p[w->a] = q[w->a] = x;
        p[o] = inv->box[2 * o];
        q[o] = p[o] + 0.5 * per;
        if (cb_topo_inverter_spread(inv, p, q) <= tol) {
            *pole = x;
            return 1;
        }
    }
    return 0;
}

typedef struct {
    double q[NQ]; /* volume, area, moments about the reference point */
    cb_status st;
    cb_error err;
} face_result;

static cb_status grow(double **p, int *cap, int need)
{
    if (need <= *cap)
        return CB_OK;
    int c = need + need / 2 + 16;
    double *np = realloc(*p, (size_t)c * sizeof *np);
    if (!np)
        return CB_ERR_NOMEM;
    *p = np;
    *cap = c;
    return CB_OK;
}

/* How far apart in 3D the ends of coedges c0 and c1 may be where one follows the other: the
 * larger of their edges' tolerances (the validator's loop test), at least gap_tol. The joint
 * is integrated as a straight segment in (u, v); a gap that wide moves the result by about
 * its square. */
static double joint_tol(const cb_topo_body *b, int c0, int c1, double gap_tol)
{
    return fmax(gap_tol, fmax(b->edges[b->coedges[c0].edge].tol,
                              b->edges[b->coedges[c1].edge].tol));
}

static cb_status face_integrate(face_result *res, const cb_topo_body *b, int f, const double c[3],
                                double scale, double rel, cb_context *ctx)
{
    const cb_topo_face *fa = &b->faces[f];
    const cb_topo_surface *s = &b->surfaces[fa->surface];
    cb_error *err = &res->err;
    double tol = b->tol > 0 ? b->tol : 1e-9 * scale;
    double gap_tol = 10 * tol + 1e-9 * scale;
    cb_topo_inverter inv;
    cb_status st = cb_topo_inverter_init(&inv, s, tol, err);
    if (st)
        return st;
    face_work w;
    memset(&w, 0, sizeof w);
    w.inv = &inv;
    w.inner_left = MAX_FACE_BISECTIONS;
    w.nurbs = s->kind == CB_SURFACE_NURBS;
    w.rel_in = INNER_FACTOR * rel;
    w.noise_in = INNER_NOISE * (1 + cb_vec3_norm(c) / scale);
    if (s->kind == CB_SURFACE_NURBS)
        w.noise_in *= fmax(1.0, 0.5 * (s->nurbs->deg_u + s->nurbs->deg_v));
    memcpy(w.c, c, sizeof w.c);
    double dims[NQ] = {3, 2, 4, 4, 4, 2, 2, 2};
    for (int q = 0; q < NQ; q++) {
        w.floor_out[q] = 1e-6 * rel * pow(scale, dims[q]);
        w.floor_in[q] = INNER_FACTOR * w.floor_out[q];
    }
    int n_co = 0;
    for (int l = fa->first; l < fa->first + fa->count; l++)
        n_co += b->loops[l].count;
    coedge_info *ci = calloc((size_t)(n_co ? n_co : 1), sizeof *ci);
    int *wrap = calloc((size_t)(2 * fa->count + 2), sizeof *wrap);
    double *xs = NULL;
    int cap_xs = 0;
    if (!ci || !wrap) {
        st = cb_error_set(err, CB_ERR_NOMEM, "mass: out of memory");
        goto done;
    }
    /* Ranges, ends on the edges, lifts by whole periods so each coedge starts where the
     * previous one ends (unless they already meet on the surface, e.g. along a pole). */
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    int any_wrap[2] = {0, 0}, k = 0;
    for (int l = fa->first; l < fa->first + fa->count; l++) {
        const cb_topo_loop *lp = &b->loops[l];
        int first = k;
        for (int cc = lp->first; cc < lp->first + lp->count; cc++, k++) {
            coedge_info *e = &ci[k];
            const cb_topo_edge *ed = &b->edges[b->coedges[cc].edge];
            /* At the edge's own tolerance, as the face's loops are sampled (brep/face.c): a
             * closed pcurve's way round is the one whose middle lies on the edge, and a
             * Boolean's cut edge lies that far (its weld distance) from its pcurve's image;
             * judged at the body's tolerance, the short way round was taken for an edge
             * running most of the way round a closed B-spline face (trj10_ch1-id-chs). */
            cb_topo_coedge_pcurve_range(&e->s0, &e->s1, b, cc, &inv, fmax(tol, ed->tol));
            e->map.pc = &b->pcurves[b->coedges[cc].pcurve];
            e->map.curve = &b->curves[ed->curve];
            e->map.t0 = ed->t0;
            e->map.t1 = ed->t1;
            e->map.convention = follows_convention(b, cc, &inv, e->s0, e->s1, tol);
            double d[2];
            coedge_node(e->start, d, &w, &e->map, e->s0);
            coedge_node(e->end, d, &w, &e->map, e->s1);
            if (k > first) {
                const double *p = ci[k - 1].end;
                /* Lifted only where the joint as it is does not close on the surface within
                 * the edges' tolerance: two coedges ending a little off a pole (a traced
                 * meridian) meet across the pole line either way round, and a lift by the
                 * nearest whole period (half a period away) made the loop wind around it. */
                if (cb_topo_inverter_spread(&inv, p, e->start) >
                    joint_tol(b, cc - 1, cc, gap_tol)) {
                    for (int i = 0; i < 2; i++)
                        if (inv.lift[i] > 0)
                            e->map.off[i] = inv.lift[i] * round((p[i] - e->start[i]) / inv.lift[i]);
                    for (int i = 0; i < 2; i++) {
                        e->start[i] += e->map.off[i];
                        e->end[i] += e->map.off[i];
                    }
                    if (cb_topo_inverter_spread(&inv, p, e->start) >
                        joint_tol(b, cc - 1, cc, gap_tol)) {
                        st = cb_error_set(err, CB_ERR_INVALID,
                                          "mass: face %d: coedges %d and %d do not meet in "
                                          "(u, v)",
                                          f, cc - 1, cc);
                        goto done;
                    }
                }
            }
            for (int i = 0; i < 2; i++) {
                lo[i] = fmin(lo[i], fmin(e->start[i], e->end[i]));
                hi[i] = fmax(hi[i], fmax(e->start[i], e->end[i]));
            }
        }
        /* Closure: the loop ends where it started, or whole periods away (around a period);
         * as above, it winds only where it does not close as it is. */
        int li = l - fa->first;
        const double *p = ci[k - 1].end, *q = ci[first].start;
        int c_last = lp->first + lp->count - 1;
        if (cb_topo_inverter_spread(&inv, p, q) > joint_tol(b, c_last, lp->first, gap_tol)) {
            double q2[2];
            for (int i = 0; i < 2; i++) {
                wrap[2 * li + i] =
                    inv.period[i] > 0 ? (int)lround((p[i] - q[i]) / inv.period[i]) : 0;
                q2[i] = q[i] + wrap[2 * li + i] * inv.period[i];
                any_wrap[i] |= wrap[2 * li + i] != 0;
            }
            if (cb_topo_inverter_spread(&inv, p, q2) > joint_tol(b, c_last, lp->first, gap_tol)) {
                st = cb_error_set(err, CB_ERR_INVALID,
                                  "mass: face %d: loop %d does not close in (u, v)", f, l);
                goto done;
            }
        }
    }
    if (any_wrap[0] && any_wrap[1]) {
        st = cb_error_set(err, CB_ERR_UNSUPPORTED,
                          "mass: face %d has loops around both periods of its surface", f);
        goto done;
    }
    /* Loops around the u period: integrate along v (periodic in u), and conversely. */
    w.a = any_wrap[0] ? 1 : 0;
    w.sign = w.a == 0 ? 1 : -1;
    int o = 1 - w.a, net = 0;
    for (int li = 0; li < fa->count; li++)
        net += wrap[2 * li + o];
    w.ref = 0.5 * (lo[w.a] + hi[w.a]);
    /* On a surface with a pole at both ends of v (a sphere), a face closed at one of them
     * (pole_v) is integrated as F dv, each loop around u closed through that pole: from its
     * end along v to the pole, and from the pole along v to its start. As -G du, a loop that
     * reaches the other pole (a hemisphere bounded by a great circle through both poles)
     * would take the whole face from its run along that pole line, where G is the integral
     * from pole to pole, but a pcurve passes over a pole as a jump in u that the integration
     * along the edge does not follow; F dv gets nothing from lines along a pole. */
    int pole_close = 0;
    double pole_v = 0;
    if (net) {
        /* The face is closed at a pole: on the left of the loops' net direction in (u, v)
         * for same_sense 1 (+v of a loop along +u, -u of a loop along +v), else the right. */
        int left = (net > 0) == (fa->same_sense != 0);
        int side = (w.a == 1) == left ? 1 : -1;
        if (!find_pole(&w.ref, &w, s, side, lo[w.a], hi[w.a], gap_tol)) {
            st = cb_error_set(err, CB_ERR_INVALID,
                              "mass: face %d: its loops wind around the surface but no pole "
                              "closes the face",
                              f);
            goto done;
        }
        double far;
        if (w.a == 1 && find_pole(&far, &w, s, -side, lo[1], hi[1], gap_tol)) {
            pole_close = 1;
            pole_v = w.ref;
            w.a = 0;
            w.sign = 1;
            w.ref = 0.5 * (lo[0] + hi[0]);
        }
    }
    w.period = inv.period[w.a];
    {
        int cap = 0;
        if (s->kind == CB_SURFACE_NURBS)
            cap = (w.a ? s->nurbs->n_v + s->nurbs->deg_v : s->nurbs->n_u + s->nurbs->deg_u) + 1;
        else if (s->profile.kind == CB_CURVE_NURBS)
            cap = s->profile.nurbs->n + s->profile.nurbs->deg + 1;
        int cap_o = 0;
        if (s->kind == CB_SURFACE_NURBS)
            cap_o = (w.a ? s->nurbs->n_u + s->nurbs->deg_u : s->nurbs->n_v + s->nurbs->deg_v) + 1;
        else if (s->profile.kind == CB_CURVE_NURBS)
            cap_o = s->profile.nurbs->n + s->profile.nurbs->deg + 1;
        w.knots = malloc((size_t)(cap + 1) * sizeof *w.knots);
        w.knots_o = malloc((size_t)(cap_o + 1) * sizeof *w.knots_o);
        w.cap_pts = 2 * cap + 64;
        w.pts = malloc((size_t)w.cap_pts * sizeof *w.pts);
        if (!w.knots || !w.knots_o || !w.pts) {
            st = cb_error_set(err, CB_ERR_NOMEM, "mass: out of memory");
            goto done;
        }
        w.n_knots = surface_knots(w.knots, cap, s, w.a);
        w.n_knots_o = surface_knots(w.knots_o, cap_o, s, 1 - w.a);
    }
    double total[NQ] = {0};
    k = 0;
    for (int l = fa->first; l < fa->first + fa->count; l++) {
        const cb_topo_loop *lp = &b->loops[l];
        int first = k, li = l - fa->first;
        for (int cc = 0; cc < lp->count; cc++, k++) {
            coedge_info *e = &ci[k];
            int need = 2 + 4 * w.n_knots_o + 64;
            if (e->map.pc->kind == CB_CURVE_NURBS)
                need += e->map.pc->nurbs->n;
            if (e->map.curve->kind == CB_CURVE_NURBS)
                need += e->map.curve->nurbs->n;
            if (grow(&xs, &cap_xs, need)) {
                st = cb_error_set(err, CB_ERR_NOMEM, "mass: out of memory");
                goto done;
            }
            int n = outer_breaks(xs, cap_xs, &w, &e->map, e->s0, e->s1);
            w.cm = &e->map;
            adaptive ad = {outer_fn,      &w, MAX_DEPTH_OUTER, ctx, 0, OUTER_NOISE * rel,
                           MAX_BISECTIONS};
            integrate(total, &ad, xs, n, rel, w.floor_out);
            if (ad.cancelled || cb_context_cancelled(ctx)) {
                st = cb_error_set(err, CB_ERR_CANCELLED, "mass: cancelled");
                goto done;
            }
            if (pole_close && cc + 1 == lp->count && wrap[2 * li] != 0) {
                /* closed through the pole (above): the two sides along v */
                const double *q = ci[first].start;
                double sides[2][4] = {{e->end[0], e->end[1], e->end[0], pole_v},
                                      {q[0], pole_v, q[0], q[1]}};
                for (int i = 0; i < 2; i++) {
                    double x01[2] = {0, 1};
                    w.seg = sides[i];
                    adaptive as = {segment_fn,    &w, MAX_DEPTH_OUTER, ctx, 0,
                                   OUTER_NOISE * rel, MAX_BISECTIONS};
                    integrate(total, &as, x01, 2, rel, w.floor_out);
                }
                continue;
            }
            /* The joint to the next coedge (the first one shifted by the loop's wrap). */
            double seg[4];
            const double *nx = cc + 1 < lp->count ? ci[k + 1].start : ci[first].start;
            seg[0] = e->end[0];
            seg[1] = e->end[1];
            for (int i = 0; i < 2; i++)
                seg[2 + i] = nx[i] + (cc + 1 < lp->count ? 0 : wrap[2 * li + i] * inv.period[i]);
            if (seg[3 - w.a] != seg[1 - w.a]) {
                /* A joint around the wrap direction is shifted back by the wrap: the inner
                 * integral is periodic there. */
                double x01[2] = {0, 1};
                w.seg = seg;
                adaptive as = {segment_fn,    &w, MAX_DEPTH_OUTER, ctx, 0, OUTER_NOISE * rel,
                               MAX_BISECTIONS};
                integrate(total, &as, x01, 2, rel, w.floor_out);
            }
        }
    }
    /* On a surface closed in u with a pole at both ends in v (a sphere), a loop that does
     * not wind bounds two regions, and which one the face is follows from the loop's sense
     * alone, not from where its pcurves lie in (u, v): a loop meeting itself across a pole
     * line (two meridians; a great circle through both poles) may lie so that it runs round
     * the region in (u, v) the other way. Its area then comes out negative, and the face is
     * the complement: the whole band u in [u0, u0 + period] between the poles (the integral
     * along its two sides v = pole to pole; the pole lines add nothing) plus the loops. */
    if ((fa->same_sense ? total[QA] : -total[QA]) < 0 && !any_wrap[0] && !any_wrap[1] &&
        w.a == 0 && inv.period[0] > 0) {
        face_work wp = w;
        wp.a = 1;
        double vs, vn;
        if (find_pole(&vn, &wp, s, 1, lo[1], hi[1], gap_tol) &&
            find_pole(&vs, &wp, s, -1, lo[1], hi[1], gap_tol)) {
            double band[NQ] = {0}, x01[2] = {0, 1};
            double sides[2][4] = {{lo[0] + inv.period[0], vs, lo[0] + inv.period[0], vn},
                                  {lo[0], vn, lo[0], vs}};
            for (int i = 0; i < 2; i++) {
                w.seg = sides[i];
                adaptive as = {segment_fn,    &w, MAX_DEPTH_OUTER, ctx, 0, OUTER_NOISE * rel,
                               MAX_BISECTIONS};
                integrate(band, &as, x01, 2, rel, w.floor_out);
            }
            /* the band integrated counter-clockwise; the loops run clockwise round their
             * face where same_sense is 0 */
            double sense = fa->same_sense ? 1 : -1;
            if (sense * (total[QA] + sense * band[QA]) > 0)
                for (int q = 0; q < NQ; q++)
                    total[q] += sense * band[q];
        }
    }
    if (w.inner_left <= 0) {
        st = cb_error_set(err, CB_ERR_NUMERIC,
                          "mass: face %d: the integrals do not converge within %ld bisections",
                          f, MAX_FACE_BISECTIONS);
        goto done;
    }
    double e_sign = fa->same_sense ? 1 : -1;
    for (int q = 0; q < NQ; q++)
        res->q[q] = total[q];
    res->q[QA] *= e_sign;
done:
    free(ci);
    free(wrap);
    free(xs);
    free(w.knots);
    free(w.knots_o);
    free(w.pts);
    cb_topo_inverter_clear(&inv);
    return st;
}

/* ---------------------------------------------------------------- shells ------------------- */

typedef struct {
    const cb_topo_body *b;
    const int *faces;
    int n;
    double c[3], scale, rel;
    cb_context *ctx;
    face_result *res;
    atomic_int done;
} shell_job;

static void shell_body(void *p, size_t begin, size_t end)
{
    shell_job *j = p;
    for (size_t i = begin; i < end; i++) {
        face_result *r = &j->res[i];
        if (cb_context_cancelled(j->ctx)) {
            r->st = cb_error_set(&r->err, CB_ERR_CANCELLED, "mass: cancelled");
            continue;
        }
        r->st = face_integrate(r, j->b, j->faces[i], j->c, j->scale, j->rel, j->ctx);
        int d = atomic_fetch_add(&j->done, 1) + 1;
        cb_context_progress(j->ctx, d, j->n, "mass properties");
    }
}

/* Preconditions of shell k (brep/mass.h); its closedness only when closed is set. */
static cb_status check_shell(const cb_topo_body *b, int k, int closed, cb_error *err)
{
    if (k < 0 || k >= b->n_shells)
        return cb_error_set(err, CB_ERR_INVALID, "mass: shell %d out of range [0, %d)", k,
                            b->n_shells);
    if (!b->edge_start)
        return cb_error_set(err, CB_ERR_INVALID,
                            "mass: the body has no incidence index (cb_topo_body_index)");
    const cb_topo_shell *sh = &b->shells[k];
    for (int f = sh->first; f < sh->first + sh->count; f++) {
        const cb_topo_face *fa = &b->faces[f];
        if (fa->count == 0)
            return cb_error_set(err, CB_ERR_INVALID, "mass: face %d has no loop", f);
        for (int l = fa->first; l < fa->first + fa->count; l++) {
            if (b->loops[l].count == 0)
                return cb_error_set(err, CB_ERR_INVALID, "mass: face %d: loop %d has no coedge", f,
                                    l);
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
                int e = b->coedges[c].edge;
                if (b->coedges[c].pcurve < 0)
                    return cb_error_set(err, CB_ERR_INVALID,
                                        "mass: face %d: coedge %d has no pcurve "
                                        "(cb_topo_compute_pcurves)",
                                        f, c);
                int in_shell = 0;
                for (int j = b->edge_start[e]; j < b->edge_start[e + 1]; j++) {
                    int g = b->loops[b->coedges[b->edge_coedges[j]].loop].face;
                    in_shell += g >= sh->first && g < sh->first + sh->count;
                }
                if (closed && in_shell != 2)
                    return cb_error_set(err, CB_ERR_INVALID,
                                        "mass: shell %d is open: edge %d is used by %d "
                                        "coedge%s of it, not 2",
                                        k, e, in_shell, in_shell == 1 ? "" : "s");
            }
        }
    }
    return CB_OK;
}

/* Sums of the face integrals of shell k about c, in face order. */
static cb_status shell_sums(double q[NQ], const cb_topo_body *b, int k, int closed,
                            const double c[3], double scale, double rel, cb_context *ctx,
                            cb_error *err)
{
    cb_status st = check_shell(b, k, closed, err);
    if (st)
        return st;
    const cb_topo_shell *sh = &b->shells[k];
    int n = sh->count;
    int *faces = malloc((size_t)(n ? n : 1) * sizeof *faces);
    face_result *res = calloc((size_t)(n ? n : 1), sizeof *res);
    if (!faces || !res) {
        free(faces);
        free(res);
        return cb_error_set(err, CB_ERR_NOMEM, "mass: out of memory");
    }
    for (int i = 0; i < n; i++)
        faces[i] = sh->first + i;
    shell_job j = {b, faces, n, {c[0], c[1], c[2]}, scale, rel, ctx, res, 0};
    atomic_init(&j.done, 0);
    st = cb_parallel_for((size_t)n, 1, cb_context_threads(ctx), shell_body, &j);
    if (st)
        st = cb_error_set(err, st, "mass: the task scheduler failed");
    for (int i = 0; i < n && !st; i++)
        if (res[i].st) {
            st = res[i].st;
            if (err)
                *err = res[i].err;
        }
    if (!st && cb_context_cancelled(ctx))
        st = cb_error_set(err, CB_ERR_CANCELLED, "mass: cancelled");
    for (int i = 0; i < n && !st; i++)
        for (int qq = 0; qq < NQ; qq++)
            q[qq] += res[i].q[qq];
    free(faces);
    free(res);
    return st;
}

static void finish_props(cb_mass_props *m, const double q[NQ], const double c[3])
{
    m->volume = q[QV];
    m->area = q[QA];
    for (int i = 0; i < 3; i++) {
        m->vector_area[i] = q[QNX + i];
        m->moment[i] = q[QX + i] + c[i] * q[QV];
        m->centroid[i] = q[QV] != 0 ? c[i] + q[QX + i] / q[QV] : c[i];
    }
}

static void reference(double c[3], double *scale, const cb_topo_body *b)
{
    cb_aabb box;
    cb_topo_body_edge_box(&box, b);
    double d[3];
    for (int i = 0; i < 3; i++) {
        c[i] = 0.5 * (box.lo[i] + box.hi[i]);
        d[i] = box.hi[i] - box.lo[i];
    }
    *scale = cb_vec3_norm(d);
    if (!(*scale > 0) || !isfinite(*scale))
        *scale = 1;
}

static cb_status check_tol(double *rel, cb_error *err)
{
    if (isnan(*rel))
        return cb_error_set(err, CB_ERR_INVALID, "mass: relative tolerance is NaN");
    if (*rel <= 0)
        *rel = CB_MASS_REL_TOL;
    return CB_OK;
}

cb_status cb_mass_shell(cb_mass_props *m, const cb_topo_body *b, int k, double rel_tol,
                        cb_context *ctx, cb_error *err)
{
    memset(m, 0, sizeof *m);
    cb_status st = check_tol(&rel_tol, err);
    if (st)
        return st;
    double c[3], scale, q[NQ] = {0};
    reference(c, &scale, b);
    if ((st = shell_sums(q, b, k, 1, c, scale, rel_tol, ctx, err)))
        return st;
    finish_props(m, q, c);
    return CB_OK;
}

cb_status cb_mass_body(cb_mass_props *m, const cb_topo_body *b, double rel_tol, cb_context *ctx,
                       cb_error *err)
{
    memset(m, 0, sizeof *m);
    cb_status st = check_tol(&rel_tol, err);
    if (st)
        return st;
    double c[3], scale, q[NQ] = {0};
    reference(c, &scale, b);
    /* Open shells of surface models (sheets) bound nothing: their area counts, not their
     * volume, as long as some closed shell gives the body a volume. */
    int *sheet = calloc((size_t)(b->n_shells ? b->n_shells : 1), sizeof *sheet), closed = 0;
    if (!sheet)
        return cb_error_set(err, CB_ERR_NOMEM, "mass: out of memory");
    cb_error first;
    cb_error_clear(&first);
    for (int k = 0; k < b->n_shells; k++) {
        cb_error e;
        cb_error_clear(&e);
        sheet[k] = b->shells[k].solid < 0 && check_shell(b, k, 0, &e) == CB_OK &&
                   check_shell(b, k, 1, !first.status ? &first : &e) != CB_OK;
        closed += !sheet[k];
    }
    if (!closed && b->n_shells) {
        free(sheet);
        *err = first;
        return first.status;
    }
    for (int k = 0; k < b->n_shells; k++) {
        double qs[NQ] = {0};
        if ((st = shell_sums(qs, b, k, !sheet[k], c, scale, rel_tol, ctx, err))) {
            free(sheet);
            return st;
        }
        if (sheet[k])
            q[QA] += qs[QA];
        else
            for (int i = 0; i < NQ; i++)
                q[i] += qs[i];
    }
    free(sheet);
    finish_props(m, q, c);
    return CB_OK;
}

/* Half the integral of (x - c) x dx over [t0, t1] of curve cu, 5-point Gauss-Legendre on the
 * interval against its two halves, halved where they differ by more than eps (kinks of a
 * B-spline's derivatives), to depth 24. */
static void cross_integral(double out[3], const cb_topo_curve *cu, double t0, double t1,
                           const double c[3], double eps, int depth)
{
    static const double X[5] = {0, -0.5384693101056831, 0.5384693101056831,
                                -0.9061798459386640, 0.9061798459386640};
    static const double W[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                0.2369268850561891, 0.2369268850561891};
    double whole[3] = {0, 0, 0}, halves[3] = {0, 0, 0};
    for (int part = 0; part < 3; part++) {
        double a = part == 0 ? t0 : part == 1 ? t0 : 0.5 * (t0 + t1);
        double z = part == 0 ? t1 : part == 1 ? 0.5 * (t0 + t1) : t1;
        double *acc = part == 0 ? whole : halves;
        for (int i = 0; i < 5; i++) {
            double d[3][3], r[3], xr[3];
            cb_topo_curve_eval_derivs(d, cu, 0.5 * (a + z) + 0.5 * (z - a) * X[i]);
            for (int q = 0; q < 3; q++)
                r[q] = d[0][q] - c[q];
            cb_vec3_cross(xr, r, d[1]);
            for (int q = 0; q < 3; q++)
                acc[q] += 0.25 * (z - a) * W[i] * xr[q];
        }
    }
    double diff[3] = {whole[0] - halves[0], whole[1] - halves[1], whole[2] - halves[2]};
    if (depth < 24 && cb_vec3_norm(diff) > eps) {
        double lo[3], hi[3];
        cross_integral(lo, cu, t0, 0.5 * (t0 + t1), c, 0.5 * eps, depth + 1);
        cross_integral(hi, cu, 0.5 * (t0 + t1), t1, c, 0.5 * eps, depth + 1);
        for (int q = 0; q < 3; q++)
            out[q] = lo[q] + hi[q];
        return;
    }
    memcpy(out, halves, sizeof halves);
}

cb_status cb_mass_area(double *area, const cb_topo_body *b, double rel_tol, cb_context *ctx,
                       cb_error *err)
{
    *area = 0;
    cb_status st = check_tol(&rel_tol, err);
    if (st)
        return st;
    double c[3], scale, sum = 0;
    reference(c, &scale, b);
    for (int k = 0; k < b->n_shells; k++) {
        double qs[NQ] = {0};
        if ((st = shell_sums(qs, b, k, 0, c, scale, rel_tol, ctx, err)))
            return st;
        sum += qs[QA];
        /* Stokes: the faces' vector area (the integral of n dA) is half the integral of
         * x x dx round their free boundary, the edges used once, each the way its coedge
         * runs (0 for a closed shell). A face integrated over the wrong region of its surface
         * breaks it, as cb_mass_closure_bound says for closed shells. */
        const cb_topo_shell *sh = &b->shells[k];
        double bd[3] = {0, 0, 0}, len = 0;
        for (int f = sh->first; f < sh->first + sh->count; f++)
            for (int l = b->faces[f].first; l < b->faces[f].first + b->faces[f].count; l++)
                for (int i = b->loops[l].first; i < b->loops[l].first + b->loops[l].count; i++) {
                    int e = b->coedges[i].edge;
                    const cb_topo_edge *ed = &b->edges[e];
                    len += cb_topo_edge_length(b, e) * fmax(b->tol, ed->tol);
                    if (b->edge_start[e + 1] - b->edge_start[e] != 1)
                        continue;
                    double v[3];
                    cross_integral(v, &b->curves[ed->curve], ed->t0, ed->t1, c,
                                   1e-12 * scale * scale, 0);
                    double sg = (ed->same_sense != 0) == (b->coedges[i].sense != 0) ? 1 : -1;
                    for (int q = 0; q < 3; q++)
                        bd[q] += sg * v[q];
                }
        double off[3] = {qs[QNX] - bd[0], qs[QNY] - bd[1], qs[QNZ] - bd[2]};
        double allow = len + 1e-9 * fabs(qs[QA]);
        if (!(cb_vec3_norm(off) <= allow))
            return cb_error_set(err, CB_ERR_NUMERIC,
                                "mass: shell %d: the faces' integrated normals do not match its "
                                "boundary (off by %.3g, the edges' tolerances allow %.3g): a "
                                "face integrated over the wrong region, the area %.10g not to "
                                "be trusted",
                                k, cb_vec3_norm(off), allow, qs[QA]);
    }
    *area = sum;
    return CB_OK;
}

double cb_mass_closure_bound(const cb_topo_body *b, double area, int edge_tols)
{
    double s = 0;
    for (int e = 0; e < b->n_edges; e++)
        s += cb_topo_edge_length(b, e) * (edge_tols ? fmax(b->tol, b->edges[e].tol) : b->tol);
    return 2 * s + 1e-9 * fabs(area);
}
