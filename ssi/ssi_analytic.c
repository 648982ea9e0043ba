/* ssi_analytic.c — two analytic surfaces: closed forms where the pair is in special position
 * (parallel, coaxial, tangent, coincident), the general route otherwise (see ssi/ssi.h,
 * cb_ssi_surfaces, and ssi/README.md "Analytic/analytic pairs").
 *
 * Closed forms give the intersection as lines, circles and plane sections of a cylinder, each
 * clipped to both surfaces' parameter ranges and sampled to the chord tolerance; the special
 * positions are decided with the tolerance tol (distances) and tol / size (directions), as a
 * B-rep decides that two faces touch. The general route writes one surface as its exact
 * rational B-spline (cb_analytic_to_nurbs) and runs the analytic/NURBS pipeline with the
 * other's exact implicit equation, so its topology is certified as for any such pair; the
 * parameters on the converted side are then those of the analytic surface again. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <flint/fmpz_vec.h>

#include "brep/bbox.h"
#include "brep/topo.h"
#include "ssi/ssi.h"
#include "ssi/ssi_tol.h"

#define PI CB_SSI_PI

/* ---------------------------------------------------------------- small vectors ------------ */

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double norm(const double a[3]) { return sqrt(dot(a, a)); }

static void cross(double c[3], const double a[3], const double b[3])
{
    double t[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0]};
    memcpy(c, t, sizeof t);
}

static void axpy(double out[3], const double p[3], double s, const double d[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = p[k] + s * d[k];
}

static void sub(double out[3], const double a[3], const double b[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = a[k] - b[k];
}

static int unit(double u[3], const double a[3])
{
    double l = norm(a);
    if (!(l > 0) || !isfinite(l))
        return 0;
    for (int k = 0; k < 3; k++)
        u[k] = a[k] / l;
    return 1;
}

/* Some unit vector perpendicular to the unit vector z. */
static void perp(double x[3], const double z[3])
{
    double e[3] = {0, 0, 0};
    int k = fabs(z[0]) <= fabs(z[1]) && fabs(z[0]) <= fabs(z[2]) ? 0
            : fabs(z[1]) <= fabs(z[2])                           ? 1
                                                                 : 2;
    e[k] = 1;
    double t[3];
    cross(t, z, e);
    unit(x, t);
}

/* ---------------------------------------------------------------- bounded surfaces --------- */

typedef struct {
    const cb_analytic_surface *a;
    double range[4]; /* bounded: finite, angular spans at most one turn */
    double per[2];   /* 2 pi for an angular direction, else 0 */
    int full[2];     /* the angular direction covers a whole turn: never clipped */
    cb_aabb box;
    const _cb_ssi_image *img; /* the B-spline a stands for (NULL: none): clipping to its
                                 domain, parameters its own */
} asurf;

static int is_angular(const cb_analytic_surface *a, int d)
{
    return d == 0 ? a->kind != CB_ANALYTIC_PLANE : a->kind == CB_ANALYTIC_TORUS;
}

/* Axial parameter of the cone's apex (r + v tan a = 0). */
static double cone_apex_v(const cb_analytic_surface *a) { return -a->r1 / tan(a->angle); }

static void box_union(cb_aabb *b, const cb_aabb *c)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = fmin(b->lo[k], c->lo[k]);
        b->hi[k] = fmax(b->hi[k], c->hi[k]);
    }
}

/* Box of the control net of the exact rational form over [u0,u1] x [v0,v1] (a cone range
 * crossing its apex in two parts). */
static int net_box(cb_aabb *box, const cb_analytic_surface *a, const double r[4])
{
    cb_nurbs_surface_t net;
    cb_nurbs_surface_init(net);
    int ok;
    if (a->kind == CB_ANALYTIC_CONE && r[2] < cone_apex_v(a) && r[3] > cone_apex_v(a)) {
        double va = cone_apex_v(a);
        cb_aabb b2;
        ok = cb_analytic_to_nurbs(net, a, r[0], r[1], r[2], va, NULL) == CB_OK;
        if (ok)
            cb_nurbs_surface_aabb(box, net);
        ok = ok && cb_analytic_to_nurbs(net, a, r[0], r[1], va, r[3], NULL) == CB_OK;
        if (ok) {
            cb_nurbs_surface_aabb(&b2, net);
            box_union(box, &b2);
        }
    } else {
        ok = cb_analytic_to_nurbs(net, a, r[0], r[1], r[2], r[3], NULL) == CB_OK;
        if (ok)
            cb_nurbs_surface_aabb(box, net);
    }
    cb_nurbs_surface_clear(net);
    return ok;
}

/* Angular directions to one turn at most, the sphere's and ellipsoid's latitude to
 * [-pi/2, pi/2]; returns 1 when every direction is then finite. */
static int asurf_set(asurf *s, const cb_ssi_surface *S)
{
    s->a = &S->analytic;
    memcpy(s->range, S->range, sizeof s->range);
    int bounded = 1;
    for (int d = 0; d < 2; d++) {
        double *lo = s->range + 2 * d, *hi = lo + 1;
        s->per[d] = is_angular(s->a, d) ? 2 * PI : 0;
        s->full[d] = 0;
        if (s->per[d] > 0) {
            if (!isfinite(*lo) || !isfinite(*hi) || *hi - *lo >= 2 * PI) {
                *lo = isfinite(*lo) ? *lo : -PI;
                *hi = *lo + 2 * PI;
                s->full[d] = 1;
            }
        } else if (d == 1 && (s->a->kind == CB_ANALYTIC_SPHERE ||
                              s->a->kind == CB_ANALYTIC_ELLIPSOID)) {
            *lo = fmax(*lo, -PI / 2);
            *hi = fmin(*hi, PI / 2);
        } else if (!isfinite(*lo) || !isfinite(*hi)) {
            bounded = 0;
        }
    }
    return bounded;
}

/* An unbounded linear direction of s limited to the parameters the box b (grown by tol)
 * spans on it. */
static void asurf_bound(asurf *s, const cb_aabb *b, double tol)
{
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int c = 0; c < 8; c++) {
        double X[3] = {(c & 1 ? b->hi[0] : b->lo[0]), (c & 2 ? b->hi[1] : b->lo[1]),
                       (c & 4 ? b->hi[2] : b->lo[2])},
               l[3];
        cb_frame_to_local(l, &s->a->frame, X);
        double uv[2] = {l[0], s->a->kind == CB_ANALYTIC_PLANE ? l[1] : l[2]};
        for (int d = 0; d < 2; d++) {
            lo[d] = fmin(lo[d], uv[d] - tol);
            hi[d] = fmax(hi[d], uv[d] + tol);
        }
    }
    for (int d = 0; d < 2; d++) {
        if (s->per[d] > 0)
            continue;
        if (!isfinite(s->range[2 * d]))
            s->range[2 * d] = lo[d];
        if (!isfinite(s->range[2 * d + 1]))
            s->range[2 * d + 1] = hi[d];
        if (s->range[2 * d + 1] < s->range[2 * d])
            s->range[2 * d + 1] = s->range[2 * d];
    }
}

/* Parameters of X on s, angular ones lifted into the window of the range: [lo, lo + 2 pi) for
 * a whole turn, else the turn centred on the range (a point just outside an end stays next to
 * that end). */
static void ainvert(double uv[2], const asurf *s, const double X[3])
{
    if (s->img) {
        cb_topo_inverter_invert(uv, s->img->inv, X, NULL);
        return;
    }
    _cb_ssi_analytic_invert(uv, s->a, X);
    for (int d = 0; d < 2; d++) {
        double per = s->per[d], lo = s->range[2 * d], hi = s->range[2 * d + 1];
        if (per <= 0)
            continue;
        double w0 = s->full[d] ? lo : 0.5 * (lo + hi) - 0.5 * per;
        uv[d] = w0 + fmod(fmod(uv[d] - w0, per) + per, per);
    }
}

/* How far inside s's range X lies, in model units, plus tol (>= 0: inside up to tol): per
 * clipped direction the parameter distance to the nearer end (negative outside; an angle
 * outside the range counts to the nearer end around the turn) times the speed |S_u| or
 * |S_v| there. */
static double amargin(const asurf *s, const double X[3], double tol)
{
    double uv[2], D[6][3], m = HUGE_VAL;
    if (s->img) {
        /* The B-spline's domain: the parameter distance of the foot point to its nearer end
         * times the speed there, per direction that does not close on itself; beyond the
         * domain the foot point lies on its boundary and the distance to it, less the proved
         * distance between the two surfaces, counts against. */
        const cb_topo_inverter *inv = s->img->inv;
        double dist = cb_topo_inverter_invert(uv, inv, X, NULL);
        cb_topo_inverter_eval_derivs(D, inv, uv[0], uv[1]);
        for (int d = 0; d < 2; d++)
            if (!(inv->period[d] > 0))
                m = fmin(m, fmin(uv[d] - inv->box[2 * d], inv->box[2 * d + 1] - uv[d]) *
                                norm(D[1 + d]));
        if (m == HUGE_VAL)
            m = norm(D[1]) + norm(D[2]);
        return fmax(m, 0) + tol - fmax(dist - s->img->dev, 0);
    }
    _cb_ssi_analytic_invert(uv, s->a, X);
    cb_analytic_eval_derivs(D, s->a, uv[0], uv[1]);
    for (int d = 0; d < 2; d++) {
        double lo = s->range[2 * d], hi = s->range[2 * d + 1], per = s->per[d], x = uv[d], g;
        if (per > 0) {
            if (s->full[d])
                continue;
            x = lo + fmod(fmod(x - lo, per) + per, per);
            g = x <= hi ? fmin(x - lo, hi - x) : -fmin(x - hi, lo + per - x);
        } else {
            g = fmin(x - lo, hi - x);
        }
        m = fmin(m, g * norm(D[1 + d]) + tol);
    }
    return m;
}

/* Unit normal S_u x S_v of s at the point X of it (0 vector at a pole or apex). */
static void anormal(double n[3], const asurf *s, const double X[3])
{
    double uv[2], D[6][3];
    if (s->img) {
        cb_topo_inverter_invert(uv, s->img->inv, X, NULL);
        cb_topo_inverter_eval_derivs(D, s->img->inv, uv[0], uv[1]);
    } else {
        _cb_ssi_analytic_invert(uv, s->a, X);
        cb_analytic_eval_derivs(D, s->a, uv[0], uv[1]);
    }
    cross(n, D[1], D[2]);
    if (!unit(n, n))
        n[0] = n[1] = n[2] = 0;
}

/* ---------------------------------------------------------------- closed-form curves ------- */

typedef enum { PR_LINE, PR_CIRCLE, PR_CYLCUT } prim_kind;

/* A curve of the intersection, before clipping:
 *   line    p + t d, t in [t0, t1] (d unit)
 *   circle  c + rad (cos t e1 + sin t e2), t in [0, 2 pi)
 *   cylcut  the point of the cylinder cyl at angle t whose axial v puts it on the plane
 *           n . X = h (n not perpendicular to the axis), t in [0, 2 pi)
 * brk: parameters where the curve must be cut (nodes: crossing points, a cone's apex). */
typedef struct {
    prim_kind kind;
    double p[3], d[3], t0, t1;
    double c[3], e1[3], e2[3], rad;
    const cb_analytic_surface *cyl;
    double n[3], h;
    int tangential;
    int nbrk;
    double brk[2];
} prim;

static void prim_eval(double X[3], const prim *c, double t)
{
    switch (c->kind) {
    case PR_LINE:
        axpy(X, c->p, t, c->d);
        break;
    case PR_CIRCLE:
        for (int k = 0; k < 3; k++)
            X[k] = c->c[k] + c->rad * (cos(t) * c->e1[k] + sin(t) * c->e2[k]);
        break;
    case PR_CYLCUT: {
        const cb_frame *f = &c->cyl->frame;
        double q[3];
        for (int k = 0; k < 3; k++)
            q[k] = f->o[k] + c->cyl->r1 * (cos(t) * f->x[k] + sin(t) * f->y[k]);
        axpy(X, q, (c->h - dot(c->n, q)) / dot(c->n, f->z), f->z);
        break;
    }
    }
}

static int prim_periodic(const prim *c) { return c->kind != PR_LINE; }

typedef struct {
    asurf s[2];
    double tol, chord, max_seg, size;
    double slack; /* clipping slack: SLACK times the size, round-off of the closed forms */
} actx;

/* Clipping slack relative to the size: a curve lying on a range's end (an edge line of both
 * faces) computes to within round-off of it and must be kept; a slack of tol would instead
 * turn a curve that only grazes a range's end into a piece of length ~ sqrt(tol r). */
#define SLACK CB_SSI_CLOSED_FORM_SLACK

static double margin(const actx *g, const prim *c, double t)
{
    double X[3];
    prim_eval(X, c, t);
    return fmin(amargin(g->s, X, g->slack), amargin(g->s + 1, X, g->slack));
}

/* Root of the margin between a and b (signs differ at the ends), by bisection. */
static double bisect(const actx *g, const prim *c, double a, double ma, double b)
{
    for (int it = 0; it < 80 && b - a > 1e-15 * (fabs(a) + fabs(b) + 1); it++) {
        double m = 0.5 * (a + b), mm = margin(g, c, m);
        if ((mm >= 0) == (ma >= 0)) {
            a = m;
            ma = mm;
        } else {
            b = m;
        }
    }
    return 0.5 * (a + b);
}

/* Extremum (sgn = 1: minimum, -1: maximum) of the margin in [a, b] by golden section. */
static double golden(const actx *g, const prim *c, double a, double b, int sgn, double *val)
{
    const double r = 0.6180339887498949;
    double x1 = b - r * (b - a), x2 = a + r * (b - a);
    double f1 = sgn * margin(g, c, x1), f2 = sgn * margin(g, c, x2);
    for (int it = 0; it < 60; it++) {
        if (f1 < f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - r * (b - a);
            f1 = sgn * margin(g, c, x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + r * (b - a);
            f2 = sgn * margin(g, c, x2);
        }
    }
    double x = f1 < f2 ? x1 : x2;
    *val = sgn * fmin(f1, f2);
    return x;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Lifts X onto both surfaces and appends it to the piece; CB_ERR_NOMEM. */
static cb_status piece_add(_cb_ssi_piece *pc, const actx *g, const double X[3])
{
    _cb_ssi_pq q;
    memset(&q, 0, sizeof q);
    ainvert(q.uv, g->s, X);
    ainvert(q.st, g->s + 1, X);
    return _cb_ssi_piece_push(pc, &q, X);
}

static cb_status sample_rec(_cb_ssi_piece *pc, const actx *g, const prim *c, double ta,
                            const double Xa[3], double tb, const double Xb[3], int depth)
{
    double tm = 0.5 * (ta + tb), Xm[3], mid[3];
    prim_eval(Xm, c, tm);
    for (int k = 0; k < 3; k++)
        mid[k] = 0.5 * (Xa[k] + Xb[k]);
    double seg = sqrt((Xb[0] - Xa[0]) * (Xb[0] - Xa[0]) + (Xb[1] - Xa[1]) * (Xb[1] - Xa[1]) +
                      (Xb[2] - Xa[2]) * (Xb[2] - Xa[2]));
    double dev = sqrt((Xm[0] - mid[0]) * (Xm[0] - mid[0]) + (Xm[1] - mid[1]) * (Xm[1] - mid[1]) +
                      (Xm[2] - mid[2]) * (Xm[2] - mid[2]));
    if (depth < 40 && (seg > g->max_seg || dev > g->chord)) {
        if (sample_rec(pc, g, c, ta, Xa, tm, Xm, depth + 1) != CB_OK)
            return CB_ERR_NOMEM;
        return sample_rec(pc, g, c, tm, Xm, tb, Xb, depth + 1);
    }
    return piece_add(pc, g, Xb);
}

/* On a side standing for a B-spline, a point where a parameter is undetermined (a pole of a
 * B-spline sphere or cone: S_u or S_v vanishes there) takes that parameter from its nearer
 * neighbour along the piece, so the piece's (u, v) run on without a jump to wherever the
 * inversion left it. */
static void piece_fix_degenerate(_cb_ssi_piece *pc, const actx *g)
{
    for (int side = 0; side < 2; side++) {
        const _cb_ssi_image *img = g->s[side].img;
        if (!img || pc->n < 2)
            continue;
        for (slong i = 0; i < pc->n; i++) {
            double *uv = side ? pc->pt[i].st : pc->pt[i].uv, D[6][3];
            cb_topo_inverter_eval_derivs(D, img->inv, uv[0], uv[1]);
            double nu = norm(D[1]), nv = norm(D[2]);
            for (int d = 0; d < 2; d++) {
                if (!((d ? nv : nu) <= 1e-9 * (nu + nv)))
                    continue;
                slong j = i > 0 ? i - 1 : i + 1;
                const double *w = side ? pc->pt[j].st : pc->pt[j].uv;
                uv[d] = w[d];
            }
        }
    }
}

/* The curve over [ta, tb] as a piece, chords within chord and max_seg (curved primitives
 * start from chords of at most pi/8 of their parameter, so no chord test is fooled). A piece
 * shorter than CB_SSI_CLOSED_FORM_SHORT tol (where a curve touches a range's end) is dropped
 * (ssi_tol.h). CB_ERR_NOMEM may leave the piece part
 * built. */
static cb_status emit_piece(_cb_ssi_piece_set *out, const actx *g, const prim *c, double ta,
                            double tb, int closed)
{
    double len = 0, Y0[3], Y1[3];
    prim_eval(Y0, c, ta);
    for (int i = 1; i <= 16 && len <= CB_SSI_CLOSED_FORM_SHORT * g->tol; i++) {
        prim_eval(Y1, c, ta + (tb - ta) * i / 16);
        len += sqrt((Y1[0] - Y0[0]) * (Y1[0] - Y0[0]) + (Y1[1] - Y0[1]) * (Y1[1] - Y0[1]) +
                    (Y1[2] - Y0[2]) * (Y1[2] - Y0[2]));
        memcpy(Y0, Y1, sizeof Y0);
    }
    if (len <= CB_SSI_CLOSED_FORM_SHORT * g->tol)
        return CB_OK;
    _cb_ssi_piece *pc = _cb_ssi_piece_set_add(out);
    if (!pc)
        return CB_ERR_NOMEM;
    pc->closed = closed;
    pc->tangential = c->tangential;
    int nseg = c->kind == PR_LINE ? 1 : (int)fmax(2, ceil((tb - ta) / (PI / 8)));
    double Xa[3];
    prim_eval(Xa, c, ta);
    cb_status st = piece_add(pc, g, Xa);
    for (int i = 1; i <= nseg && st == CB_OK; i++) {
        double t = i == nseg ? tb : ta + (tb - ta) * i / nseg, X[3];
        prim_eval(X, c, t);
        if (closed && i == nseg)
            memcpy(X, pc->xyz, sizeof X); /* the loop ends exactly where it starts */
        st = sample_rec(pc, g, c, ta + (tb - ta) * (i - 1) / nseg, Xa, t, X, 0);
        memcpy(Xa, X, sizeof Xa);
    }
    if (st == CB_OK)
        piece_fix_degenerate(pc, g);
    return st;
}

/* Clips the curve to both ranges (margin >= 0) and appends its pieces. The parameter interval
 * is sampled at 256 points; every sign change of the margin is refined by bisection, and every
 * sampled local minimum above zero (maximum below) is searched by golden section for a dip
 * through zero between the samples, so short excursions are not stepped over. CB_ERR_NOMEM. */
static cb_status clip_prim(_cb_ssi_piece_set *out, const actx *g, const prim *c)
{
    enum { NS = CB_SSI_CLOSED_FORM_SAMPLES };
    int per = prim_periodic(c);
    double t0 = per ? 0 : c->t0, t1 = per ? 2 * PI : c->t1;
    if (!(t1 > t0))
        return CB_OK;
    double ts[NS + 1], ms[NS + 1], roots[4 * NS + 8];
    int nr = 0;
    for (int i = 0; i <= NS; i++) {
        ts[i] = t0 + (t1 - t0) * i / NS;
        ms[i] = (per && i == NS) ? ms[0] : margin(g, c, ts[i]);
    }
    for (int i = 0; i < NS; i++)
        if ((ms[i] >= 0) != (ms[i + 1] >= 0))
            roots[nr++] = bisect(g, c, ts[i], ms[i], ts[i + 1]);
    for (int i = 0; i <= NS; i++) {
        int ip = i > 0 ? i - 1 : (per ? NS - 1 : -1), in = i < NS ? i + 1 : (per ? 1 : -1);
        if (ip < 0 || in < 0)
            continue;
        double a = i > 0 ? ts[ip] : ts[ip] - (t1 - t0), b = i < NS ? ts[in] : ts[in] + (t1 - t0);
        int sgn = 0;
        if (ms[i] >= 0 && ms[i] <= ms[ip] && ms[i] <= ms[in])
            sgn = 1;
        else if (ms[i] < 0 && ms[i] >= ms[ip] && ms[i] >= ms[in])
            sgn = -1;
        if (!sgn || (per && i == NS))
            continue;
        double val, x = golden(g, c, a, b, sgn, &val);
        if ((val >= 0) != (ms[i] >= 0)) {
            roots[nr++] = bisect(g, c, a, ms[ip], x);
            roots[nr++] = bisect(g, c, x, val, b);
        }
    }
    for (int k = 0; k < c->nbrk; k++)
        roots[nr++] = c->brk[k];
    /* Periodic roots into [t0, t1); drop duplicates. */
    for (int k = 0; k < nr; k++)
        if (per)
            roots[k] = t0 + fmod(fmod(roots[k] - t0, t1 - t0) + (t1 - t0), t1 - t0);
    qsort(roots, (size_t)nr, sizeof(double), cmp_double);
    int m = 0;
    for (int k = 0; k < nr; k++)
        if (m == 0 || roots[k] - roots[m - 1] > 1e-13 * (t1 - t0))
            roots[m++] = roots[k];
    nr = m;
    cb_status st = CB_OK;
    if (per) {
        if (nr == 0)
            return margin(g, c, t0) >= 0 ? emit_piece(out, g, c, t0, t1, 1) : CB_OK;
        for (int k = 0; k < nr && st == CB_OK; k++) {
            double a = roots[k], b = k + 1 < nr ? roots[k + 1] : roots[0] + (t1 - t0);
            if (b - a > 1e-12 * (t1 - t0) && margin(g, c, 0.5 * (a + b)) >= 0)
                st = emit_piece(out, g, c, a, b, 0);
        }
        return st;
    }
    double prev = t0;
    for (int k = 0; k <= nr && st == CB_OK; k++) {
        double b = k < nr ? roots[k] : t1;
        if (b <= prev || b > t1)
            continue;
        if (b - prev > 1e-12 * (t1 - t0) && margin(g, c, 0.5 * (prev + b)) >= 0)
            st = emit_piece(out, g, c, prev, b, 0);
        prev = b;
    }
    return st;
}

/* An isolated contact point, kept when inside both ranges; CB_ERR_NOMEM. */
static cb_status emit_point(_cb_ssi_piece_set *out, const actx *g, const double X[3])
{
    if (fmin(amargin(g->s, X, g->slack), amargin(g->s + 1, X, g->slack)) < 0)
        return CB_OK;
    _cb_ssi_piece *pc = _cb_ssi_piece_set_add(out);
    if (!pc)
        return CB_ERR_NOMEM;
    pc->isolated = pc->tangential = 1;
    return piece_add(pc, g, X);
}

/* ---------------------------------------------------------------- the closed forms --------- */

typedef struct {
    int coincident, general, n;
    prim pr[8];
    int np;
    double pts[8][3];
} plan;

static prim *plan_prim(plan *P, prim_kind kind, int tangential)
{
    prim *c = P->pr + P->n++;
    memset(c, 0, sizeof(*c));
    c->kind = kind;
    c->tangential = tangential;
    return c;
}

/* A line through p along d over the parameters where it lies in both boxes (grown by tol). */
static void plan_line(plan *P, const actx *g, const double p[3], const double d[3],
                      int tangential)
{
    double u[3];
    if (P->n >= 8 || !unit(u, d))
        return;
    double t0 = -HUGE_VAL, t1 = HUGE_VAL;
    for (int s = 0; s < 2; s++) {
        const cb_aabb *b = &g->s[s].box;
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        for (int c = 0; c < 8; c++) {
            double X[3] = {(c & 1 ? b->hi[0] : b->lo[0]), (c & 2 ? b->hi[1] : b->lo[1]),
                           (c & 4 ? b->hi[2] : b->lo[2])},
                   q[3];
            sub(q, X, p);
            lo = fmin(lo, dot(q, u));
            hi = fmax(hi, dot(q, u));
        }
        t0 = fmax(t0, lo - g->tol);
        t1 = fmin(t1, hi + g->tol);
    }
    if (!(t1 > t0))
        return;
    prim *c = plan_prim(P, PR_LINE, tangential);
    memcpy(c->p, p, sizeof c->p);
    memcpy(c->d, u, sizeof c->d);
    c->t0 = t0;
    c->t1 = t1;
}

static void plan_circle(plan *P, const double c0[3], const double z[3], double rad,
                        int tangential)
{
    if (P->n >= 8)
        return;
    prim *c = plan_prim(P, PR_CIRCLE, tangential);
    memcpy(c->c, c0, sizeof c->c);
    c->rad = rad;
    perp(c->e1, z);
    cross(c->e2, z, c->e1);
}

static void plan_point(plan *P, const double X[3])
{
    if (P->np < 8)
        memcpy(P->pts[P->np++], X, 3 * sizeof(double));
}

/* Plane n . X = h cut of the cylinder cy (n not perpendicular to its axis). */
static prim *plan_cylcut(plan *P, const cb_analytic_surface *cy, const double n[3], double h)
{
    if (P->n >= 8)
        return NULL;
    prim *c = plan_prim(P, PR_CYLCUT, 0);
    c->cyl = cy;
    memcpy(c->n, n, sizeof c->n);
    c->h = h;
    return c;
}

/* Plane / plane: a line, or parallel (coincident or apart). */
static void pp_plane_plane(plan *P, const actx *g, const cb_analytic_surface *A,
                           const cb_analytic_surface *B, double ta)
{
    const double *nA = A->frame.z, *nB = B->frame.z;
    double d[3], w[3];
    cross(d, nA, nB);
    sub(w, B->frame.o, A->frame.o);
    if (norm(d) <= ta) {
        P->coincident = fabs(dot(nA, w)) <= g->tol;
        return;
    }
    /* The point of the line nearest A's origin: p = oA + a nA' ... solved in the basis
     * (nA, nB, d): p = oA + x, x . nA = 0, x . nB = nB . w, x . d = 0. */
    unit(d, d);
    double m[3];
    cross(m, d, nA); /* in A's plane, perpendicular to the line */
    double s = dot(nB, w) / dot(nB, m), p[3];
    axpy(p, A->frame.o, s, m);
    plan_line(P, g, p, d, 0);
}

/* Plane / cylinder with its axis parallel to the plane (within ta): 0, 1 (tangent) or 2
 * rulings; otherwise the plane section of the cylinder. */
static void pp_plane_cylinder(plan *P, const actx *g, const cb_analytic_surface *pl,
                              const cb_analytic_surface *cy, double ta)
{
    const double *n = pl->frame.z, *z = cy->frame.z;
    double r = cy->r1, w[3];
    sub(w, cy->frame.o, pl->frame.o);
    if (fabs(dot(n, z)) > ta) {
        plan_cylcut(P, cy, n, dot(n, pl->frame.o));
        return;
    }
    double np[3], side[3];
    axpy(np, n, -dot(n, z), z);
    unit(np, np);
    cross(side, z, np);
    double delta = dot(n, w), ad = fabs(delta), sg = delta >= 0 ? 1 : -1, p[3];
    if (ad > r + g->tol)
        return;
    if (fabs(ad - r) <= g->tol) {
        /* Tangent along a ruling: the line halfway between the plane and the cylinder. */
        axpy(p, cy->frame.o, -sg * 0.5 * (r + ad), np);
        plan_line(P, g, p, z, 1);
        return;
    }
    double hw = sqrt(r * r - delta * delta), q[3];
    axpy(q, cy->frame.o, -delta, np);
    axpy(p, q, hw, side);
    plan_line(P, g, p, z, 0);
    axpy(p, q, -hw, side);
    plan_line(P, g, p, z, 0);
}

/* Cylinder / cylinder. Parallel axes: coaxial (coincident or apart) or the lines where the
 * cross-section circles meet (tangent externally or internally: one line). Crossing axes
 * with equal radii: two ellipses through the two contact points. Skew axes at distance
 * rA + rB: one contact point. Otherwise the general route. */
static void pp_cyl_cyl(plan *P, const actx *g, const cb_analytic_surface *A,
                       const cb_analytic_surface *B, double ta)
{
    const double *zA = A->frame.z, *zB = B->frame.z;
    double rA = A->r1, rB = B->r1, w[3], c[3], tol = g->tol;
    sub(w, B->frame.o, A->frame.o);
    cross(c, zA, zB);
    if (norm(c) <= ta) {
        double wp[3];
        axpy(wp, w, -dot(w, zA), zA);
        double D = norm(wp);
        if (D <= tol) {
            P->coincident = fabs(rA - rB) <= tol;
            return;
        }
        double e[3], f[3], p[3];
        unit(e, wp);
        cross(f, zA, e);
        if (D > rA + rB + tol || D < fabs(rA - rB) - tol)
            return;
        if (fabs(D - (rA + rB)) <= tol) {
            axpy(p, A->frame.o, rA + 0.5 * (D - rA - rB), e);
            plan_line(P, g, p, zA, 1);
            return;
        }
        if (fabs(D - fabs(rA - rB)) <= tol) {
            /* One inside the other, touching where the inner one is farthest from the outer
             * one's axis: on A at +rA e (B inside) or -rA e (A inside); B's point there is
             * at D + rB e or D - rB e from A's axis. Halfway between. */
            double sA = rA > rB ? rA : -rA, sB = rA > rB ? D + rB : D - rB;
            axpy(p, A->frame.o, 0.5 * (sA + sB), e);
            plan_line(P, g, p, zA, 1);
            return;
        }
        double x = (D * D + rA * rA - rB * rB) / (2 * D), hw = sqrt(fmax(0, rA * rA - x * x)),
               q[3];
        axpy(q, A->frame.o, x, e);
        axpy(p, q, hw, f);
        plan_line(P, g, p, zA, 0);
        axpy(p, q, -hw, f);
        plan_line(P, g, p, zA, 0);
        return;
    }
    double n[3];
    unit(n, c);
    double Dp = dot(n, w), aD = fabs(Dp);
    if (aD > rA + rB + tol)
        return;
    /* Nearest points of the axes: oA + a zA and oB + b zB. */
    double k = dot(zA, zB), den = 1 - k * k, wa = dot(w, zA), wb = dot(w, zB);
    double a = (wa - k * wb) / den, b = (k * wa - wb) / den, pA[3], pB[3];
    axpy(pA, A->frame.o, a, zA);
    axpy(pB, B->frame.o, b, zB);
    if (fabs(aD - (rA + rB)) <= tol) {
        double e[3], p[3];
        sub(e, pB, pA);
        if (!unit(e, e))
            memcpy(e, n, sizeof e);
        axpy(p, pA, rA + 0.5 * (aD - rA - rB), e);
        plan_point(P, p);
        return;
    }
    if (aD <= tol && fabs(rA - rB) <= tol) {
        /* Equal radii, axes meeting at pA: the two ellipses in the planes through pA with
         * normals zA - zB and zA + zB, crossing at pA +- rA n (where the surfaces touch). */
        for (int s = -1; s <= 1; s += 2) {
            double m[3];
            axpy(m, zA, s, zB);
            unit(m, m);
            prim *cc = plan_cylcut(P, A, m, dot(m, pA));
            if (!cc)
                return;
            for (int q = -1; q <= 1; q += 2) {
                double X[3], l[3];
                axpy(X, pA, q * rA, n);
                cb_frame_to_local(l, &A->frame, X);
                cc->brk[cc->nbrk++] = atan2(l[1], l[0]);
            }
        }
        return;
    }
    P->general = 1;
}

/* Plane / cone with the apex on the plane (within tol): the rulings in the plane (two, one
 * tangent, or only the apex). Otherwise the general route. */
static void pp_plane_cone(plan *P, const actx *g, const cb_analytic_surface *pl,
                          const cb_analytic_surface *co, double ta)
{
    double q[3], w[3];
    axpy(q, co->frame.o, cone_apex_v(co), co->frame.z);
    sub(w, q, pl->frame.o);
    const double *n = pl->frame.z, *z = co->frame.z;
    if (fabs(dot(n, w)) > g->tol) {
        P->general = 1;
        return;
    }
    double p[3];
    axpy(p, z, -dot(z, n), n);
    double cb = norm(p), beta = atan2(fabs(dot(z, n)), cb), a = co->angle;
    if (fabs(beta - a) <= ta) {
        /* Tangent along one ruling; cut at the apex (a singular point of the cone). */
        int n0 = P->n;
        unit(p, p);
        plan_line(P, g, q, p, 1);
        if (P->n > n0)
            P->pr[n0].brk[P->pr[n0].nbrk++] = 0;
        return;
    }
    if (beta > a) {
        plan_point(P, q);
        return;
    }
    double pq[3], qq[3];
    unit(pq, p);
    cross(qq, n, pq);
    double gam = acos(fmin(1, cos(a) / cb));
    for (int s = -1; s <= 1; s += 2) {
        double d[3];
        for (int k = 0; k < 3; k++)
            d[k] = cos(gam) * pq[k] + s * sin(gam) * qq[k];
        int n0 = P->n;
        plan_line(P, g, q, d, 0);
        if (P->n > n0)
            P->pr[n0].brk[P->pr[n0].nbrk++] = 0; /* the apex: the two lines cross there */
    }
}

/* Cylinder / sphere off the axis: apart, or touching at one point from outside or inside;
 * otherwise the general route. */
static void pp_cyl_sphere(plan *P, const actx *g, const cb_analytic_surface *cy,
                          const cb_analytic_surface *sp)
{
    double w[3], wp[3], e[3], p[3], r = cy->r1, R = sp->r1, tol = g->tol;
    sub(w, sp->frame.o, cy->frame.o);
    axpy(wp, w, -dot(w, cy->frame.z), cy->frame.z);
    double D = norm(wp);
    unit(e, wp);
    double foot[3];
    axpy(foot, cy->frame.o, dot(w, cy->frame.z), cy->frame.z);
    if (D > r + R + tol || D + R < r - tol)
        return;
    if (fabs(D - (r + R)) <= tol) {
        axpy(p, foot, r + 0.5 * (D - r - R), e);
        plan_point(P, p);
        return;
    }
    if (fabs(D + R - r) <= tol) {
        axpy(p, foot, 0.5 * (r + D + R), e);
        plan_point(P, p);
        return;
    }
    P->general = 1;
}

/* Plane / torus with the torus' axis in the plane (within ta and tol): the two meridian
 * circles of radius r about the centre's points at distance R along the plane, in the
 * plane; 0 when the plane does not hold the axis. (The general route puts these circles on
 * the lines between its rational patches, quarter turns about the axis when the plane is
 * placed with the torus' frame: traced on both sides of such a line, they came out stitched
 * with spurs doubling back.) */
static int pp_plane_meridian(plan *P, const actx *g, const cb_analytic_surface *pl,
                             const cb_analytic_surface *to, double ta)
{
    const double *n = pl->frame.z, *z = to->frame.z;
    double w[3], e[3];
    sub(w, to->frame.o, pl->frame.o);
    if (fabs(dot(n, z)) > ta || fabs(dot(n, w)) > g->tol)
        return 0;
    cross(e, z, n);
    if (!unit(e, e))
        return 0;
    for (int k = 0; k < 2; k++) {
        double c[3];
        axpy(c, to->frame.o, k ? -to->r1 : to->r1, e);
        plan_circle(P, c, n, to->r2, 0);
    }
    return 1;
}

/* ---------------------------------------------------------------- coaxial surfaces --------- */

/* Profiles of surfaces of revolution about a common axis (o, z) in the meridian plane with
 * signed radius rho and height h = z . (X - o): lines through (rho, h) = q along dir, and
 * circles about q of radius rad. The plane perpendicular to the axis is the line h = const;
 * a cylinder the lines rho = +-r; a cone the two lines through its apex; a sphere a circle
 * on the axis; a torus the circles about (+-R, h). */
typedef struct {
    int circle;
    double q[2], dir[2], rad;
} prof;

static int profiles(prof *out, const cb_analytic_surface *s, const double o[3],
                    const double z[3])
{
    double w[3];
    sub(w, s->frame.o, o);
    double h = dot(w, z), sg = dot(s->frame.z, z) >= 0 ? 1 : -1;
    switch (s->kind) {
    case CB_ANALYTIC_PLANE:
        out[0] = (prof){0, {0, h}, {1, 0}, 0};
        return 1;
    case CB_ANALYTIC_CYLINDER:
        out[0] = (prof){0, {s->r1, 0}, {0, 1}, 0};
        out[1] = (prof){0, {-s->r1, 0}, {0, 1}, 0};
        return 2;
    case CB_ANALYTIC_CONE: {
        double t = tan(s->angle), l = sqrt(1 + t * t);
        out[0] = (prof){0, {s->r1, h}, {sg * t / l, 1 / l}, 0};
        out[1] = (prof){0, {-s->r1, h}, {-sg * t / l, 1 / l}, 0};
        return 2;
    }
    case CB_ANALYTIC_SPHERE:
        out[0] = (prof){1, {0, h}, {0, 0}, s->r1};
        return 1;
    case CB_ANALYTIC_TORUS:
        out[0] = (prof){1, {s->r1, h}, {0, 0}, s->r2};
        out[1] = (prof){1, {-s->r1, h}, {0, 0}, s->r2};
        return 2;
    default:
        return 0;
    }
}

/* Meeting points of two profiles: -1 when they coincide (within tol), else their number
 * (<= 2) with tangent flags. */
static int prof_meet(double pt[2][2], int tang[2], const prof *a, const prof *b, double tol,
                     double ta)
{
    if (!a->circle && !b->circle) {
        double cr = a->dir[0] * b->dir[1] - a->dir[1] * b->dir[0];
        double dq[2] = {b->q[0] - a->q[0], b->q[1] - a->q[1]};
        if (fabs(cr) <= ta)
            return fabs(dq[0] * a->dir[1] - dq[1] * a->dir[0]) <= tol ? -1 : 0;
        double t = (dq[0] * b->dir[1] - dq[1] * b->dir[0]) / cr;
        pt[0][0] = a->q[0] + t * a->dir[0];
        pt[0][1] = a->q[1] + t * a->dir[1];
        tang[0] = 0;
        return 1;
    }
    if (a->circle && b->circle) {
        double dq[2] = {b->q[0] - a->q[0], b->q[1] - a->q[1]}, d = hypot(dq[0], dq[1]);
        double R1 = a->rad, R2 = b->rad;
        if (d <= tol)
            return fabs(R1 - R2) <= tol ? -1 : 0;
        if (d > R1 + R2 + tol || d < fabs(R1 - R2) - tol)
            return 0;
        double e[2] = {dq[0] / d, dq[1] / d}, f[2] = {-e[1], e[0]};
        if (fabs(d - (R1 + R2)) <= tol || fabs(d - fabs(R1 - R2)) <= tol) {
            /* Tangent: halfway between the two circles' points on the centre line. */
            double s1 = fabs(d - (R1 + R2)) <= tol ? R1 : (R1 > R2 ? R1 : -R1);
            double s2 = fabs(d - (R1 + R2)) <= tol ? d - R2 : (R1 > R2 ? d + R2 : d - R2);
            double s = 0.5 * (s1 + s2);
            pt[0][0] = a->q[0] + s * e[0];
            pt[0][1] = a->q[1] + s * e[1];
            tang[0] = 1;
            return 1;
        }
        double x = (d * d + R1 * R1 - R2 * R2) / (2 * d), hw = sqrt(fmax(0, R1 * R1 - x * x));
        for (int k = 0; k < 2; k++) {
            double sg = k ? -1 : 1;
            pt[k][0] = a->q[0] + x * e[0] + sg * hw * f[0];
            pt[k][1] = a->q[1] + x * e[1] + sg * hw * f[1];
            tang[k] = 0;
        }
        return 2;
    }
    const prof *L = a->circle ? b : a, *C = a->circle ? a : b;
    double dq[2] = {C->q[0] - L->q[0], C->q[1] - L->q[1]};
    double t = dq[0] * L->dir[0] + dq[1] * L->dir[1];
    double foot[2] = {L->q[0] + t * L->dir[0], L->q[1] + t * L->dir[1]};
    double off[2] = {C->q[0] - foot[0], C->q[1] - foot[1]}, dd = hypot(off[0], off[1]);
    if (dd > C->rad + tol)
        return 0;
    if (fabs(dd - C->rad) <= tol) {
        /* Tangent: halfway between the line and the circle. */
        double s = dd > 0 ? 0.5 * (1 - C->rad / dd) : 0;
        pt[0][0] = foot[0] + s * off[0];
        pt[0][1] = foot[1] + s * off[1];
        tang[0] = 1;
        return 1;
    }
    double hw = sqrt(C->rad * C->rad - dd * dd);
    for (int k = 0; k < 2; k++) {
        double sg = k ? -1 : 1;
        pt[k][0] = foot[0] + sg * hw * L->dir[0];
        pt[k][1] = foot[1] + sg * hw * L->dir[1];
        tang[k] = 0;
    }
    return 2;
}

static int has_axis(const cb_analytic_surface *s)
{
    return s->kind == CB_ANALYTIC_CYLINDER || s->kind == CB_ANALYTIC_CONE ||
           s->kind == CB_ANALYTIC_TORUS;
}

/* A common axis (o, z) of A and B as surfaces of revolution (a plane about its normals, a
 * sphere about the lines through its centre), within tol and ta; 0 when there is none. */
static int common_axis(double o[3], double z[3], const cb_analytic_surface *A,
                       const cb_analytic_surface *B, double tol, double ta)
{
    const cb_analytic_surface *S[2] = {A, B};
    for (int k = 0; k < 2; k++) {
        const cb_analytic_surface *X = S[k], *Y = S[1 - k];
        if (!has_axis(X))
            continue;
        double w[3], c[3];
        sub(w, Y->frame.o, X->frame.o);
        if (Y->kind == CB_ANALYTIC_PLANE) {
            cross(c, X->frame.z, Y->frame.z);
        } else if (Y->kind == CB_ANALYTIC_SPHERE) {
            cross(c, X->frame.z, w);
            if (norm(c) > tol)
                return 0;
            c[0] = c[1] = c[2] = 0;
        } else if (has_axis(Y)) {
            cross(c, X->frame.z, Y->frame.z);
            if (norm(c) > ta)
                return 0;
            cross(c, X->frame.z, w);
            if (norm(c) > tol)
                return 0;
            c[0] = c[1] = c[2] = 0;
        } else {
            return 0;
        }
        if (Y->kind == CB_ANALYTIC_PLANE && norm(c) > ta)
            return 0;
        memcpy(o, X->frame.o, 3 * sizeof(double));
        memcpy(z, X->frame.z, 3 * sizeof(double));
        return 1;
    }
    if (A->kind == CB_ANALYTIC_SPHERE && B->kind == CB_ANALYTIC_SPHERE) {
        double w[3];
        sub(w, B->frame.o, A->frame.o);
        memcpy(o, A->frame.o, 3 * sizeof(double));
        if (!(norm(w) > tol) || !unit(z, w))
            memcpy(z, A->frame.z, 3 * sizeof(double));
        return 1;
    }
    for (int k = 0; k < 2; k++)
        if (S[k]->kind == CB_ANALYTIC_SPHERE && S[1 - k]->kind == CB_ANALYTIC_PLANE) {
            memcpy(o, S[k]->frame.o, 3 * sizeof(double));
            memcpy(z, S[1 - k]->frame.z, 3 * sizeof(double));
            return 1;
        }
    return 0;
}

/* Coaxial surfaces: the profiles' meeting points turned about the axis (circles; points on
 * the axis are isolated contacts), tangent where the profiles touch. */
static void pp_coaxial(plan *P, const actx *g, const cb_analytic_surface *A,
                       const cb_analytic_surface *B, const double o[3], const double z[3],
                       double ta)
{
    prof pa[2], pb[2];
    int na = profiles(pa, A, o, z), nb = profiles(pb, B, o, z);
    double got[16][2];
    int ng = 0;
    for (int i = 0; i < na; i++)
        for (int j = 0; j < nb; j++) {
            double pt[2][2];
            int tang[2], k = prof_meet(pt, tang, pa + i, pb + j, g->tol, ta);
            if (k < 0) {
                P->coincident = 1;
                return;
            }
            for (int q = 0; q < k; q++) {
                double rho = pt[q][0], h = pt[q][1];
                if (rho < -g->tol)
                    continue; /* the mirror image of a point with rho > 0 */
                int dup = 0;
                for (int m = 0; m < ng && !dup; m++)
                    dup = hypot(fabs(got[m][0]) - fabs(rho), got[m][1] - h) <= g->tol;
                if (dup)
                    continue;
                got[ng][0] = rho;
                got[ng][1] = h;
                ng++;
                double c[3];
                axpy(c, o, h, z);
                if (rho <= g->tol)
                    plan_point(P, c);
                else
                    plan_circle(P, c, z, rho, tang[q]);
            }
        }
}

/* ---------------------------------------------------------------- coincidence -------------- */

/* 1 when the exact implicit equations of a and b (cb_implicit_from_analytic: primitive, sign
 * normalised) are equal, i.e. proportional: the same algebraic surface exactly. */
static int same_equation(const cb_analytic_surface *a, const cb_analytic_surface *b)
{
    cb_implicit_t F, G;
    cb_implicit_init(F);
    cb_implicit_init(G);
    cb_error err;
    int same = cb_implicit_from_analytic(F, a, &err) == CB_OK &&
               cb_implicit_from_analytic(G, b, &err) == CB_OK && F->deg == G->deg &&
               _fmpz_vec_equal(F->c, G->c, cb_poly3_len((int)F->deg));
    cb_implicit_clear(F);
    cb_implicit_clear(G);
    return same;
}

/* ---------------------------------------------------------------- general route ------------ */

int _cb_ssi_implicit_degree(const cb_analytic_surface *a)
{
    return a->kind == CB_ANALYTIC_PLANE ? 1 : (a->kind == CB_ANALYTIC_TORUS ? 4 : 2);
}

static int param_degree(const cb_analytic_surface *a)
{
    return a->kind == CB_ANALYTIC_PLANE ? 1 : 2;
}

/* Box b {u0, u1, v0, v1} in the exact form's parameters, to the analytic surface's (ts: q's
 * surface as a topology surface). */
static void box_back(double b[4], const cb_topo_surface *ts, const asurf *q)
{
    for (int e = 0; e < 2; e++) {
        const double st[2] = {b[e], b[2 + e]};
        double uv[2];
        cb_topo_surface_nurbs_param(uv, ts, q->range, 1, st);
        b[e] = uv[0];
        b[2 + e] = uv[1];
    }
}

/* The side converted to NURBS (1: B) gets its own parameters back: each output point, and each
 * mark whose parameters are that side's, inverted onto the analytic surface, region and failure
 * boxes mapped; patch indices of that side become -1. */
static void general_fix(cb_ssi_result_t t, const asurf *q, int side)
{
    for (slong c = 0; c < t->n_curves; c++)
        for (slong i = 0; i < t->curve[c].n; i++) {
            cb_ssi_point *p = t->curve[c].pt + i;
            ainvert(side ? p->uv_b : p->uv_a, q, p->xyz);
        }
    for (slong k = 0; k < t->n_points; k++) {
        cb_ssi_point *p = &t->point[k].p;
        ainvert(side ? p->uv_b : p->uv_a, q, p->xyz);
    }
    for (slong k = 0; k < t->n_coincident; k++)
        *(side ? &t->coincident[k].patch_b : &t->coincident[k].patch_a) = -1;
    /* Region and failure boxes: each direction of the exact form maps monotonically onto the
     * analytic parameter (cb_topo_surface_nurbs_param), so the corners map to the corners. */
    cb_topo_surface ts;
    cb_topo_surface_init(&ts);
    ts.kind = CB_SURFACE_ANALYTIC;
    ts.analytic = *q->a;
    for (slong k = 0; k < t->n_regions; k++) {
        cb_ssi_region *g = t->region + k;
        *(side ? &g->patch_b : &g->patch_a) = -1;
        box_back(side ? g->box_b : g->box_a, &ts, q);
    }
    for (slong k = 0; k < t->n_failed; k++) {
        cb_ssi_failure *f = t->failed + k;
        *(side ? &f->patch_b : &f->patch_a) = -1;
        if (f->has_box)
            box_back(side ? f->box_b : f->box_a, &ts, q);
    }
    cb_topo_surface_clear(&ts);
    for (slong k = 0; k < t->n_marks; k++) {
        cb_ssi_mark *m = t->mark + k;
        if (m->q_side == side) {
            ainvert(m->uv, q, m->xyz);
            m->patch = -1;
        }
    }
}

static double surf_dist(const asurf *s, const double uv[2], const double X[3])
{
    double p[3], d[3];
    if (s->img)
        cb_topo_inverter_eval(p, s->img->inv, uv[0], uv[1]);
    else
        cb_analytic_eval(p, s->a, uv[0], uv[1]);
    sub(d, p, X);
    return norm(d);
}

/* Distance of an output point to side's surface s at its parameters on it, recorded in r
 * (the largest so far). */
static void side_dist(cb_ssi_result_t r, const asurf *s, int side, const cb_ssi_point *p)
{
    double *m = side ? &r->max_dist_b : &r->max_dist_a;
    *m = fmax(*m, surf_dist(s, side ? p->uv_b : p->uv_a, p->xyz));
}

/* The same for both surfaces. */
static void result_dist(cb_ssi_result_t r, const actx *g, const cb_ssi_point *p)
{
    side_dist(r, g->s, 0, p);
    side_dist(r, g->s + 1, 1, p);
}

/* Runs A and B as cb_ssi_surfaces with each side k whose conv[k] is set written as its exact
 * rational B-spline over its range (cb_analytic_to_nurbs_exact; an[k] its analytic
 * description), and maps the result back (general_fix). an[k] is NULL for a NURBS side; the
 * largest distances to an analytic side are measured on it again. o: the options of the run
 * (recognition off: the converted nets would be recognised and come back here). A side that
 * cannot be converted is a refusal of the pair, recorded in r. route names the caller in the
 * messages of refusals. */
static cb_status run_converted(cb_ssi_result_t r, const cb_ssi_surface *A,
                               const cb_ssi_surface *B, const asurf *const an[2],
                               const int conv[2], int fa, int fb, const cb_ssi_opts *o,
                               const char *route, cb_error *err)
{
    cb_nurbs_surface_t net[2];
    cb_ssi_surface S[2] = {*A, *B};
    cb_status st = CB_OK;
    for (int k = 0; k < 2; k++) {
        cb_nurbs_surface_init(net[k]);
        const asurf *q = an[k];
        if (!conv[k])
            continue;
        if (st == CB_OK)
            st = cb_analytic_to_nurbs_exact(net[k], q->a, q->range[0], q->range[1], q->range[2],
                                            q->range[3], err);
        if (st != CB_OK && st != CB_ERR_NOMEM) {
            char msg[200];
            snprintf(msg, sizeof msg, "%s: %s as a rational B-spline: %.120s", route,
                     k ? "B" : "A", err ? err->msg : "");
            if (err)
                cb_error_clear(err);
            r->pairs_total++;
            st = _cb_ssi_add_failure(r, fa, fb, -1, -1, CB_ERR_UNSUPPORTED, msg);
            cb_nurbs_surface_clear(net[0]);
            cb_nurbs_surface_clear(net[1]);
            if (st != CB_OK)
                return cb_error_set(err, st, "ssi: out of memory recording an uncertified "
                                    "face pair");
            return CB_OK;
        }
        cb_ssi_surface_set_nurbs(S + k, net[k]);
    }
    if (st == CB_OK) {
        cb_ssi_result_t t;
        cb_ssi_result_init(t);
        st = cb_ssi_surfaces(t, S, S + 1, fa, fb, o, err);
        if (st == CB_OK) {
            for (int k = 0; k < 2; k++)
                if (conv[k])
                    general_fix(t, an[k], k);
            for (slong k = 0; k < t->n_failed; k++) {
                char msg[200];
                snprintf(msg, sizeof msg, "%s (%s as rational B-spline): %.140s", route,
                         conv[0] && conv[1] ? "A and B" : (conv[0] ? "A" : "B"),
                         t->failed[k].msg);
                memcpy(t->failed[k].msg, msg, sizeof msg);
            }
            for (int k = 0; k < 2; k++) {
                if (!an[k])
                    continue;
                *(k ? &t->max_dist_b : &t->max_dist_a) = 0;
                for (slong c = 0; c < t->n_curves; c++)
                    for (slong i = 0; i < t->curve[c].n; i++)
                        side_dist(t, an[k], k, t->curve[c].pt + i);
                for (slong i = 0; i < t->n_points; i++)
                    side_dist(t, an[k], k, &t->point[i].p);
            }
            if (_cb_ssi_result_move(r, t) != CB_OK)
                st = cb_error_set(err, CB_ERR_NOMEM, "ssi: out of memory collecting the "
                                  "converted pair's result");
        }
        cb_ssi_result_clear(t);
    }
    cb_nurbs_surface_clear(net[0]);
    cb_nurbs_surface_clear(net[1]);
    return st;
}

/* The general route. The side whose parameterisation, substituted into the other's equation,
 * gives the lower degree is written as its exact rational B-spline (B on a tie) and the pair
 * runs as analytic/NURBS. The conversion is exact in binary where the angular ranges are whole
 * quarter turns (cb_analytic_to_nurbs_exact): a contact or node of the two surfaces then stays
 * one in phi, where cos(pi/4) rounded would make it a near-miss the topology cannot certify
 * (the paper's Table 4 torus/ellipsoid pairs). When even that degree is 8 or more (torus
 * against torus: phi of bidegree (8, 8), a minute of topology) both are converted and the pair
 * runs as NURBS/NURBS, where the subdivision route takes it. */
static cb_status general_route(cb_ssi_result_t r, const actx *g, int fa, int fb,
                               const cb_ssi_opts *opts, cb_error *err)
{
    const cb_analytic_surface *a = g->s[0].a, *b = g->s[1].a;
    int da = _cb_ssi_implicit_degree(b) * param_degree(a),
        db = _cb_ssi_implicit_degree(a) * param_degree(b);
    int conv[2] = {da < db, da >= db};
    if (FLINT_MIN(da, db) >= 8)
        conv[0] = conv[1] = 1;
    /* The sides with the ranges asurf_set bounded. */
    cb_ssi_surface S[2];
    cb_ssi_surface_set_analytic(S, a, g->s[0].range);
    cb_ssi_surface_set_analytic(S + 1, b, g->s[1].range);
    cb_ssi_opts o = *opts;
    o.tol = g->tol;
    o.chord = g->chord;
    o.recognise = 0; /* the converted nets are recognised: no way back to here */
    const asurf *an[2] = {g->s, g->s + 1};
    return run_converted(r, S, S + 1, an, conv, fa, fb, &o, "general route", err);
}

cb_status _cb_ssi_analytic_as_nurbs(cb_ssi_result_t r, const cb_ssi_surface *A,
                                    const cb_ssi_surface *B, int face_a, int face_b,
                                    const cb_ssi_opts *opts, cb_error *err)
{
    int k = A->kind == CB_SSI_ANALYTIC ? 0 : 1;
    const cb_ssi_surface *S = k ? B : A;
    asurf q;
    memset(&q, 0, sizeof q);
    if (!asurf_set(&q, S)) {
        /* An unbounded direction limited to the B-spline's box, as for analytic pairs. */
        cb_aabb box;
        cb_nurbs_surface_aabb(&box, (k ? A : B)->nurbs);
        asurf_bound(&q, &box, fmax(opts->tol, 0));
    }
    /* The analytic side is replaced by its conversion over q's range; the other is as given. */
    const asurf *an[2] = {k ? NULL : &q, k ? &q : NULL};
    int conv[2] = {!k, k};
    cb_ssi_opts o = *opts;
    o.recognise = 0;
    return run_converted(r, A, B, an, conv, face_a, face_b, &o, "phi above the degree limit",
                         err);
}

/* ---------------------------------------------------------------- driver ------------------- */

cb_status _cb_ssi_analytic_pair(cb_ssi_result_t r, const cb_ssi_surface *A,
                                const cb_ssi_surface *B, int face_a, int face_b,
                                const cb_ssi_opts *opts, cb_error *err)
{
    const _cb_ssi_image *none[2] = {NULL, NULL};
    return _cb_ssi_analytic_pair_img(r, A, B, none, face_a, face_b, opts, err);
}

cb_status _cb_ssi_analytic_pair_img(cb_ssi_result_t r, const cb_ssi_surface *A,
                                    const cb_ssi_surface *B, const _cb_ssi_image *const img[2],
                                    int face_a, int face_b, const cb_ssi_opts *opts,
                                    cb_error *err)
{
    actx g;
    memset(&g, 0, sizeof g);
    int ba = asurf_set(g.s, A), bb = asurf_set(g.s + 1, B);
    g.s[0].img = img[0];
    g.s[1].img = img[1];
    if (!ba && !bb)
        return cb_error_set(err, CB_ERR_INVALID,
                            "ssi: %s and %s both unbounded: give one of them a finite range",
                            cb_analytic_kind_name(A->analytic.kind),
                            cb_analytic_kind_name(B->analytic.kind));
    /* Boxes of the bounded sides first; an unbounded side is then limited to the other's. */
    for (int pass = 0; pass < 2; pass++)
        for (int k = 0; k < 2; k++) {
            int bounded = k ? bb : ba;
            if (bounded != (pass == 0))
                continue;
            if (!bounded)
                asurf_bound(g.s + k, &g.s[1 - k].box, 0);
            if (!net_box(&g.s[k].box, g.s[k].a, g.s[k].range))
                return cb_error_set(err, CB_ERR_INVALID,
                                    "ssi: %s range [%g, %g] x [%g, %g] is not valid",
                                    cb_analytic_kind_name(g.s[k].a->kind), g.s[k].range[0],
                                    g.s[k].range[1], g.s[k].range[2], g.s[k].range[3]);
        }
    cb_aabb all = g.s[0].box;
    box_union(&all, &g.s[1].box);
    double size = 0;
    for (int k = 0; k < 3; k++)
        size += (all.hi[k] - all.lo[k]) * (all.hi[k] - all.lo[k]);
    size = sqrt(size);
    if (!(size > 0))
        size = 1;
    g.size = size;
    g.tol = opts->tol > 0 ? opts->tol : 1e-6 * size;
    g.chord = opts->chord > 0 ? opts->chord : 1e-3 * size;
    g.max_seg = 0.05 * size;
    g.slack = SLACK * size;
    double ta = g.tol / size;
    r->tol = g.tol;
    if (!cb_aabb_overlap(&g.s[0].box, &g.s[1].box, g.tol)) {
        /* Culled, as the patch routes count separated boxes (not certified nor empty). */
        r->pairs_total++;
        r->pairs_culled++;
        return CB_OK;
    }

    /* Closed forms, with the pair ordered by kind. */
    const cb_analytic_surface *a = g.s[0].a, *b = g.s[1].a;
    if (b->kind < a->kind) {
        const cb_analytic_surface *t = a;
        a = b;
        b = t;
    }
    plan P;
    memset(&P, 0, sizeof P);
    double o[3], z[3];
    if (a->kind == CB_ANALYTIC_ELLIPSOID || b->kind == CB_ANALYTIC_ELLIPSOID)
        P.general = 1;
    else if (a->kind == CB_ANALYTIC_PLANE && b->kind == CB_ANALYTIC_PLANE)
        pp_plane_plane(&P, &g, a, b, ta);
    else if (common_axis(o, z, a, b, g.tol, ta))
        pp_coaxial(&P, &g, a, b, o, z, ta);
    else if (a->kind == CB_ANALYTIC_PLANE && b->kind == CB_ANALYTIC_CYLINDER)
        pp_plane_cylinder(&P, &g, a, b, ta);
    else if (a->kind == CB_ANALYTIC_CYLINDER && b->kind == CB_ANALYTIC_CYLINDER)
        pp_cyl_cyl(&P, &g, a, b, ta);
    else if (a->kind == CB_ANALYTIC_PLANE && b->kind == CB_ANALYTIC_CONE)
        pp_plane_cone(&P, &g, a, b, ta);
    else if (a->kind == CB_ANALYTIC_CYLINDER && b->kind == CB_ANALYTIC_SPHERE)
        pp_cyl_sphere(&P, &g, a, b);
    else if (!(a->kind == CB_ANALYTIC_PLANE && b->kind == CB_ANALYTIC_TORUS &&
               pp_plane_meridian(&P, &g, a, b, ta)))
        P.general = 1;
    /* Surfaces of the general route that coincide (ellipsoids) are found there by proof: phi
     * identically zero, or bounded within tol (ssi_coincide.c). */
    if (P.general && (img[0] || img[1]))
        return CB_OK;
    if (P.general)
        return general_route(r, &g, face_a, face_b, opts, err);

    r->pairs_total++;
    r->pairs_closed_form++;
    if (P.coincident) {
        /* A point of A (the middle of its range) and the normals of both there. Exact when
         * the exact equations agree; otherwise the closed form's comparison within tol. */
        double X[3], na[3], nb[3];
        if (img[0]) /* a point of the B-spline A stands for */
            cb_topo_inverter_eval(X, img[0]->inv, 0.5 * (img[0]->inv->box[0] + img[0]->inv->box[1]),
                                  0.5 * (img[0]->inv->box[2] + img[0]->inv->box[3]));
        else
            cb_analytic_eval(X, g.s[0].a, 0.5 * (g.s[0].range[0] + g.s[0].range[1]),
                             0.5 * (g.s[0].range[2] + g.s[0].range[3]));
        anormal(na, g.s, X);
        anormal(nb, g.s + 1, X);
        r->pairs_coincident++;
        int exact = same_equation(g.s[0].a, g.s[1].a);
        if (!_cb_ssi_add_coincident(r, face_a, face_b, -1, -1, dot(na, nb) > 0, X, exact,
                                    g.tol))
            return cb_error_set(err, CB_ERR_NOMEM,
                                "ssi: out of memory recording coincident surfaces");
        if (exact) {
            r->pairs_certified++;
            return CB_OK;
        }
        r->pairs_within_tolerance++;
        cb_ssi_region *rg =
            _cb_ssi_add_region(r, CB_SSI_REGION_COINCIDENCE, face_a, face_b, -1, -1, g.tol);
        if (!rg)
            return cb_error_set(err, CB_ERR_NOMEM,
                                "ssi: out of memory recording coincident surfaces");
        memcpy(rg->box_a, g.s[0].range, sizeof rg->box_a);
        memcpy(rg->box_b, g.s[1].range, sizeof rg->box_b);
        for (int k = 0; k < 3; k++) {
            rg->lo[k] = fmax(g.s[0].box.lo[k], g.s[1].box.lo[k]);
            rg->hi[k] = fmin(g.s[0].box.hi[k], g.s[1].box.hi[k]);
        }
        return CB_OK;
    }
    r->pairs_certified++;
    _cb_ssi_piece_set set;
    _cb_ssi_piece_set_init(&set);
    cb_status st = CB_OK;
    for (int k = 0; k < P.n && st == CB_OK; k++)
        st = clip_prim(&set, &g, P.pr + k);
    for (int k = 0; k < P.np && st == CB_OK; k++)
        st = emit_point(&set, &g, P.pts[k]);
    if (set.n == 0)
        r->pairs_empty++;
    slong c0 = r->n_curves, p0 = r->n_points;
    _cb_ssi_stitch_set ss = {&set, -1, -1, {NAN, NAN, NAN, NAN}, {NAN, NAN, NAN, NAN},
                             CB_SSI_CERTIFIED};
    _cb_ssi_stitch_opts so = {0, face_a, face_b, g.tol, g.chord, 1, {{{NAN, NAN}, {NAN, NAN}},
                                                                      {{NAN, NAN}, {NAN, NAN}}}};
    if (st == CB_OK)
        st = _cb_ssi_stitch(r, &ss, 1, &so);
    _cb_ssi_piece_set_clear(&set);
    if (st != CB_OK)
        return cb_error_set(err, st, "ssi: out of memory building the closed-form curves");
    for (slong c = c0; c < r->n_curves; c++)
        for (slong i = 0; i < r->curve[c].n; i++)
            result_dist(r, &g, r->curve[c].pt + i);
    for (slong k = p0; k < r->n_points; k++)
        result_dist(r, &g, &r->point[k].p);
    return CB_OK;
}
