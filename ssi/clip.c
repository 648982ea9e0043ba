/* clip.c — lifting traced curves to 3D, refining points onto both surfaces, and clipping to
 * the implicitised patch's parameter box (paper section 4.4). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ssi/inversion.h"
#include "ssi/ssi.h"
#include "ssi/ssi_tol.h"

/* --------------------------------------------------------------- pieces -------------------- */

void _cb_ssi_piece_init(_cb_ssi_piece *p)
{
    memset(p, 0, sizeof(*p));
    _cb_ssi_end_init(p->end);
    _cb_ssi_end_init(p->end + 1);
}

void _cb_ssi_piece_clear(_cb_ssi_piece *p)
{
    free(p->pt);
    free(p->xyz);
    _cb_ssi_end_clear(p->end);
    _cb_ssi_end_clear(p->end + 1);
    _cb_ssi_piece_init(p);
}

cb_status _cb_ssi_piece_push(_cb_ssi_piece *p, const _cb_ssi_pq *q, const double X[3])
{
    if (p->n == p->alloc) {
        /* alloc grows only once both arrays have: a larger pt alone is harmless. */
        slong alloc = p->alloc ? 2 * p->alloc : 32;
        _cb_ssi_pq *pt = realloc(p->pt, (size_t)alloc * sizeof(*pt));
        if (!pt)
            return CB_ERR_NOMEM;
        p->pt = pt;
        double *xyz = realloc(p->xyz, (size_t)alloc * 3 * sizeof(double));
        if (!xyz)
            return CB_ERR_NOMEM;
        p->xyz = xyz;
        p->alloc = alloc;
    }
    p->pt[p->n] = *q;
    memcpy(p->xyz + 3 * p->n, X, 3 * sizeof(double));
    p->n++;
    return CB_OK;
}

void _cb_ssi_piece_set_init(_cb_ssi_piece_set *ps)
{
    ps->n = ps->alloc = 0;
    ps->p = NULL;
}

void _cb_ssi_piece_set_clear(_cb_ssi_piece_set *ps)
{
    for (slong i = 0; i < ps->n; i++)
        _cb_ssi_piece_clear(ps->p + i);
    free(ps->p);
    _cb_ssi_piece_set_init(ps);
}

_cb_ssi_piece *_cb_ssi_piece_set_add(_cb_ssi_piece_set *ps)
{
    if (ps->n == ps->alloc) {
        slong alloc = ps->alloc ? 2 * ps->alloc : 8;
        _cb_ssi_piece *q = realloc(ps->p, (size_t)alloc * sizeof(*q));
        if (!q)
            return NULL;
        ps->p = q;
        ps->alloc = alloc;
    }
    _cb_ssi_piece_init(ps->p + ps->n);
    return ps->p + ps->n++;
}

/* --------------------------------------------------------------- evaluation ---------------- */

/* Point and first derivatives of a Dixon patch at local (u, v), in the polynomial form (valid
 * outside [0,1]^2 too, where the continuation of an outside point needs it). */
static void patch_eval(double X[3], double Xu[3], double Xv[3], const cb_dixon_patch_struct *P,
                       double u, double v)
{
    slong m = P->m, n = P->n, blk = (m + 1) * (n + 1);
    double val[4], du[4], dv[4];
    for (int q = 0; q < 4; q++) {
        const double *c = P->cd + q * blk;
        double f = 0, fu = 0, fv = 0;
        for (slong i = m; i >= 0; i--) {
            double r = 0, rv = 0;
            for (slong j = n; j >= 0; j--) {
                rv = rv * v + r;
                r = r * v + c[i * (n + 1) + j];
            }
            fu = fu * u + f;
            f = f * u + r;
            fv = fv * u + rv;
        }
        val[q] = f;
        du[q] = fu;
        dv[q] = fv;
    }
    double w = val[3];
    for (int k = 0; k < 3; k++) {
        X[k] = val[k] / w;
        if (Xu)
            Xu[k] = (du[k] - X[k] * du[3]) / w;
        if (Xv)
            Xv[k] = (dv[k] - X[k] * dv[3]) / w;
    }
}

void _cb_ssi_lift(double X[3], const void *geom, double sigma, double tau)
{
    const _cb_ssi_pair_geom *g = geom;
    patch_eval(X, NULL, NULL, g->q, sigma, tau);
}

static void p_eval(double X[3], double Xu[3], double Xv[3], const _cb_ssi_pair_geom *g,
                   double u, double v)
{
    if (g->p_analytic) {
        double d[6][3];
        cb_analytic_eval_derivs(d, &g->an, u, v);
        memcpy(X, d[0], sizeof(d[0]));
        memcpy(Xu, d[1], sizeof(d[1]));
        memcpy(Xv, d[2], sizeof(d[2]));
    } else {
        patch_eval(X, Xu, Xv, g->p, u, v);
    }
}

static double wrap_near(double x, double ref, double period)
{
    return period > 0 ? x + period * nearbyint((ref - x) / period) : x;
}

/* Parameters of X on the analytic surface (closed forms in the local frame); angular ones the
 * lift nearest ref (or in [range lo, lo + 2 pi) without ref). */
void _cb_ssi_analytic_invert(double uv[2], const cb_analytic_surface *a, const double X[3])
{
    double l[3];
    cb_frame_to_local(l, &a->frame, X);
    double rho = hypot(l[0], l[1]);
    switch (a->kind) {
    case CB_ANALYTIC_PLANE:
        uv[0] = l[0];
        uv[1] = l[1];
        break;
    case CB_ANALYTIC_CYLINDER:
        uv[0] = atan2(l[1], l[0]);
        uv[1] = l[2];
        break;
    case CB_ANALYTIC_CONE:
        uv[0] = atan2(l[1], l[0]);
        uv[1] = l[2];
        if (a->r1 + l[2] * tan(a->angle) < 0)
            uv[0] += CB_SSI_PI;
        break;
    case CB_ANALYTIC_SPHERE:
        uv[0] = atan2(l[1], l[0]);
        uv[1] = atan2(l[2], rho);
        break;
    case CB_ANALYTIC_TORUS:
        uv[0] = atan2(l[1], l[0]);
        uv[1] = atan2(l[2], rho - a->r1);
        break;
    case CB_ANALYTIC_ELLIPSOID:
        uv[0] = atan2(l[1] / a->r2, l[0] / a->r1);
        uv[1] = atan2(l[2] / a->r3, hypot(l[0] / a->r1, l[1] / a->r2));
        break;
    }
}

static void analytic_invert(double uv[2], const _cb_ssi_pair_geom *g, const double X[3],
                            const double *ref)
{
    _cb_ssi_analytic_invert(uv, &g->an, X);
    for (int i = 0; i < 2; i++) {
        double per = g->an_period[i];
        if (per <= 0)
            continue;
        double r = ref ? ref[i] : (isfinite(g->an_range[2 * i]) ? g->an_range[2 * i] + CB_SSI_PI : 0);
        uv[i] = wrap_near(uv[i], r, per);
    }
}

/* --------------------------------------------------------------- refinement ---------------- */

/* Gauss-Newton with minimum-norm steps on r = P(u, v) - Q(s, t) over the free parameters
 * (bits of pq->fixed held). Returns |r| at the end; X the midpoint. */
static double refine(_cb_ssi_pq *pq, double X[3], const _cb_ssi_pair_geom *g)
{
    double best = HUGE_VAL, x[4] = {pq->uv[0], pq->uv[1], pq->st[0], pq->st[1]}, xb[4];
    memcpy(xb, x, sizeof x);
    for (int it = 0; it < 40; it++) {
        double P[3], Pu[3], Pv[3], Q[3], Qs[3], Qt[3], r[3];
        p_eval(P, Pu, Pv, g, x[0], x[1]);
        patch_eval(Q, Qs, Qt, g->q, x[2], x[3]);
        for (int k = 0; k < 3; k++)
            r[k] = P[k] - Q[k];
        double nr = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        if (!(nr < best)) {
            if (it > 0)
                break;
        } else {
            best = nr;
            memcpy(xb, x, sizeof x);
            for (int k = 0; k < 3; k++)
                X[k] = 0.5 * (P[k] + Q[k]);
        }
        if (nr <= 1e-5 * g->tol)
            break;
        double J[3][4];
        for (int k = 0; k < 3; k++) {
            J[k][0] = Pu[k];
            J[k][1] = Pv[k];
            J[k][2] = -Qs[k];
            J[k][3] = -Qt[k];
        }
        for (int c = 0; c < 4; c++)
            if (pq->fixed & (1u << c))
                for (int k = 0; k < 3; k++)
                    J[k][c] = 0;
        /* (J J^T + mu I) y = r, step = -J^T y: the least change of parameters that removes the
         * residual to first order; mu keeps tangential contacts (rank-deficient J) finite. */
        double A[3][3], tr = 0;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double sum = 0;
                for (int c = 0; c < 4; c++)
                    sum += J[a][c] * J[b][c];
                A[a][b] = sum;
            }
        tr = A[0][0] + A[1][1] + A[2][2];
        for (int a = 0; a < 3; a++)
            A[a][a] += 1e-14 * tr + 1e-300;
        double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                     A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
        if (det == 0 || !isfinite(det))
            break;
        double y[3];
        for (int c = 0; c < 3; c++) {
            double M[3][3];
            memcpy(M, A, sizeof M);
            for (int k = 0; k < 3; k++)
                M[k][c] = r[k];
            y[c] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                    M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                    M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
                   det;
        }
        for (int c = 0; c < 4; c++)
            x[c] -= J[0][c] * y[0] + J[1][c] * y[1] + J[2][c] * y[2];
        /* Q stays in its patch box: the tracer's curve is inside it. */
        for (int c = 2; c < 4; c++)
            x[c] = x[c] < 0 ? 0 : (x[c] > 1 ? 1 : x[c]);
    }
    pq->uv[0] = xb[0];
    pq->uv[1] = xb[1];
    pq->st[0] = xb[2];
    pq->st[1] = xb[3];
    return best;
}

/* --------------------------------------------------------------- inside P's box ------------ */

static const double PARAM_EPS = 1e-10;

static int analytic_inside(const _cb_ssi_pair_geom *g, const double uv[2])
{
    for (int i = 0; i < 2; i++) {
        double lo = g->an_range[2 * i], hi = g->an_range[2 * i + 1], per = g->an_period[i];
        double eps = PARAM_EPS * (1 + fabs(uv[i]));
        if (per > 0 && isfinite(lo)) {
            if (hi - lo >= per - eps)
                continue;
            double x = lo + fmod(fmod(uv[i] - lo, per) + per, per);
            if (!(x <= hi + eps || x >= lo + per - eps))
                return 0;
        } else if (uv[i] < lo - eps || uv[i] > hi + eps) {
            return 0;
        }
    }
    return 1;
}

static int inside_p(const _cb_ssi_pair_geom *g, const _cb_ssi_pq *pq, double gap)
{
    if (gap > 10 * g->tol)
        return 0;
    if (g->p_analytic)
        return analytic_inside(g, pq->uv);
    for (int i = 0; i < 2; i++)
        if (pq->uv[i] < -PARAM_EPS || pq->uv[i] > 1 + PARAM_EPS)
            return 0;
    return 1;
}

/* Boundary of P's box crossed between a (inside) and b (outside): the crossing with the least
 * interpolation fraction, among the directions in which b is outside (a curve running along
 * one side crosses it back and forth by round-off while it leaves through another). Sets *dir
 * (0 u, 1 v), *val and returns the fraction, or -1. */
static double crossing(int *dir, double *val, const _cb_ssi_pair_geom *g, const _cb_ssi_pq *a,
                       const _cb_ssi_pq *b)
{
    double best = -1;
    int out[2] = {1, 1};
    if (!g->p_analytic)
        for (int i = 0; i < 2; i++)
            out[i] = b->uv[i] < -PARAM_EPS || b->uv[i] > 1 + PARAM_EPS;
    if (!out[0] && !out[1])
        out[0] = out[1] = 1;
    for (int i = 0; i < 2; i++) {
        double xa = a->uv[i], xb = b->uv[i];
        if (xa == xb || !out[i])
            continue;
        double lo = g->p_analytic ? g->an_range[2 * i] : 0;
        double hi = g->p_analytic ? g->an_range[2 * i + 1] : 1;
        double per = g->p_analytic ? g->an_period[i] : 0;
        double cand[6];
        int nc = 0;
        if (per > 0 && isfinite(lo)) {
            if (hi - lo >= per - PARAM_EPS)
                continue;
            double k = floor((xa - lo) / per);
            for (int d = -1; d <= 1; d++) {
                cand[nc++] = lo + (k + d) * per;
                cand[nc++] = hi + (k + d) * per;
            }
        } else {
            if (isfinite(lo))
                cand[nc++] = lo;
            if (isfinite(hi))
                cand[nc++] = hi;
        }
        for (int c = 0; c < nc; c++) {
            double f = (cand[c] - xa) / (xb - xa);
            /* a at the side already, past it by round-off (a curve crossing the side at a
             * sample): the crossing is a itself. */
            if (f < 0 && fabs(cand[c] - xa) <= PARAM_EPS * (1 + fabs(xa)))
                f = 0;
            if (f >= 0 && f <= 1 && (best < 0 || f < best)) {
                best = f;
                *dir = i;
                *val = cand[c];
            }
        }
    }
    return best;
}

/* The point where the curve leaves P's box between samples a (inside) and b (outside),
 * refined onto the boundary; a when that fails. */
static void split_point(_cb_ssi_pq *out, double X[3], double *gap, const _cb_ssi_pair_geom *g,
                        const _cb_ssi_pq *a, const double Xa[3], double gap_a,
                        const _cb_ssi_pq *b)
{
    int dir = 0;
    double val = 0, f = crossing(&dir, &val, g, a, b);
    *out = *a;
    memcpy(X, Xa, 3 * sizeof(double));
    *gap = gap_a;
    if (f < 0)
        return;
    _cb_ssi_pq s;
    for (int i = 0; i < 2; i++) {
        s.uv[i] = a->uv[i] + f * (b->uv[i] - a->uv[i]);
        s.st[i] = a->st[i] + f * (b->st[i] - a->st[i]);
    }
    s.uv[dir] = val;
    s.fixed = 1u << dir;
    double Xs[3], gs = refine(&s, Xs, g);
    /* The refinement may slide along the curve (Q's parameters are free) to another crossing
     * of the side, where the start between a and b was poor (b placed by another preimage of a
     * rational P): the crossing between a and b lies within their distance of a. */
    double Xb[3];
    patch_eval(Xb, NULL, NULL, g->q, b->st[0], b->st[1]);
    double dab = sqrt((Xb[0] - Xa[0]) * (Xb[0] - Xa[0]) + (Xb[1] - Xa[1]) * (Xb[1] - Xa[1]) +
                      (Xb[2] - Xa[2]) * (Xb[2] - Xa[2]));
    double das = sqrt((Xs[0] - Xa[0]) * (Xs[0] - Xa[0]) + (Xs[1] - Xa[1]) * (Xs[1] - Xa[1]) +
                      (Xs[2] - Xa[2]) * (Xs[2] - Xa[2]));
    if (gs <= g->tol && das <= dab + 10 * g->tol) {
        *out = s;
        memcpy(X, Xs, sizeof Xs);
        *gap = gs;
    }
}

/* --------------------------------------------------------------- one traced curve ---------- */

typedef struct {
    _cb_ssi_pq pq;
    double X[3], gap;
    int in;
} sample;

/* (u, v) of the point of the spline P nearest X, by Gauss-Newton on P(u, v) - X from uv
 * (at most 30 steps, each kept only if the distance drops). Q's parameters are not touched:
 * the joint refinement that follows then needs only a round-off correction, so it cannot slide
 * the point along the curve (two traced edges meeting at a vertex keep a common end). */
static void p_project(double uv[2], const _cb_ssi_pair_geom *g, const double X[3])
{
    double P[3], Pu[3], Pv[3];
    patch_eval(P, Pu, Pv, g->p, uv[0], uv[1]);
    double d2 = (P[0] - X[0]) * (P[0] - X[0]) + (P[1] - X[1]) * (P[1] - X[1]) +
                (P[2] - X[2]) * (P[2] - X[2]);
    for (int it = 0; it < 30 && d2 > 0; it++) {
        double r[3] = {X[0] - P[0], X[1] - P[1], X[2] - P[2]};
        double a = 0, b = 0, c = 0, ru = 0, rv = 0;
        for (int k = 0; k < 3; k++) {
            a += Pu[k] * Pu[k];
            b += Pu[k] * Pv[k];
            c += Pv[k] * Pv[k];
            ru += Pu[k] * r[k];
            rv += Pv[k] * r[k];
        }
        double det = a * c - b * b;
        if (!(fabs(det) > 0) || !isfinite(det))
            break;
        double nu = uv[0] + (c * ru - b * rv) / det, nv = uv[1] + (a * rv - b * ru) / det;
        double Q[3], Qu[3], Qv[3];
        patch_eval(Q, Qu, Qv, g->p, nu, nv);
        double e2 = (Q[0] - X[0]) * (Q[0] - X[0]) + (Q[1] - X[1]) * (Q[1] - X[1]) +
                    (Q[2] - X[2]) * (Q[2] - X[2]);
        if (!(e2 < d2))
            break;
        uv[0] = nu;
        uv[1] = nv;
        d2 = e2;
        memcpy(P, Q, sizeof P);
        memcpy(Pu, Qu, sizeof Pu);
        memcpy(Pv, Qv, sizeof Pv);
    }
}

/* The Dixon inversion's parameters for a starting point: preimages up to 1e3 tol off. */
static void start_params(cb_inversion_params *par, const _cb_ssi_pair_geom *g)
{
    cb_inversion_params_default(par);
    par->dist_tol = 1e3 * g->tol;
}

/* 0 when the Dixon inversion of X (start_params) certainly has no preimage inside P's box: P
 * is a polynomial patch and X is farther than dist_tol from the box of its control points
 * (which holds the patch), grown by what an inside preimage may add: the parameter slack
 * param_tol times the derivative bound (m + n) diag, and the round-off of the polish's
 * power-basis evaluation, (2 (m + n) + 6) 2^-53 times the coefficients' sum, at most
 * 3^(m + n) times the largest control coordinate. 1 otherwise. */
static int p_may_hold(const _cb_ssi_pair_geom *g, const double X[3])
{
    if (!g->p_polynomial)
        return 1;
    cb_inversion_params par;
    start_params(&par, g);
    const cb_aabb *b = &g->p_net;
    double d2 = 0, diag2 = 0, big = 0;
    for (int k = 0; k < 3; k++) {
        double e = fmax(fmax(b->lo[k] - X[k], X[k] - b->hi[k]), 0);
        d2 += e * e;
        diag2 += (b->hi[k] - b->lo[k]) * (b->hi[k] - b->lo[k]);
        big = fmax(big, fmax(fabs(b->lo[k]), fabs(b->hi[k])));
    }
    double mn = (double)(g->p->m + g->p->n);
    double grow = 2 * par.param_tol * mn * sqrt(diag2) +
                  (2 * mn + 6) * 0x1p-53 * pow(3, mn) * big;
    return !(sqrt(d2) > 2 * (par.dist_tol + grow)); /* twice: slack for the bound itself */
}

/* Initial (u, v) on P of the point X: analytic closed form, or Dixon inversion (an inside
 * preimage preferred), or for a planar patch the nearest point of a coarse grid projected
 * onto the patch. */
static void p_start(double uv[2], const _cb_ssi_pair_geom *g, const double X[3])
{
    if (g->p_analytic) {
        analytic_invert(uv, g, X, NULL);
        return;
    }
    uv[0] = uv[1] = 0.5;
    if (g->p_pencil) {
        cb_inversion_params par;
        start_params(&par, g);
        cb_inversion_t inv;
        cb_inversion_init(inv);
        cb_error err;
        if (cb_inversion_solve(inv, g->p_pencil, g->p, X, &par, &err) == CB_OK && inv->n > 0) {
            slong k = 0;
            for (slong i = 0; i < inv->n; i++)
                if (inv->pt[i].inside && (!inv->pt[k].inside || inv->pt[i].dist < inv->pt[k].dist))
                    k = i;
            /* Solutions are in the caller's domain; the pair works in [0,1]^2. */
            const double *d = g->p->domain;
            uv[0] = (inv->pt[k].u - d[0]) / (d[1] - d[0]);
            uv[1] = (inv->pt[k].v - d[2]) / (d[3] - d[2]);
            cb_inversion_clear(inv);
            return;
        }
        cb_inversion_clear(inv);
    }
    double best = HUGE_VAL;
    for (int i = 0; i <= 16; i++)
        for (int j = 0; j <= 16; j++) {
            double P[3];
            patch_eval(P, NULL, NULL, g->p, i / 16.0, j / 16.0);
            double d = (P[0] - X[0]) * (P[0] - X[0]) + (P[1] - X[1]) * (P[1] - X[1]) +
                       (P[2] - X[2]) * (P[2] - X[2]);
            if (d < best) {
                best = d;
                uv[0] = i / 16.0;
                uv[1] = j / 16.0;
            }
        }
    p_project(uv, g, X);
}

/* The section 4.4 decision for a spline P: the sample's point X lies on the trimmed patch
 * iff the Dixon inversion has a solution inside the box. Planar patches (no pencil) keep the
 * Newton decision already made. Where the inversion finds no preimage at all, not even outside
 * the box, while the sample has one inside it (Newton's, within 10 tol: s->in), the
 * inversion has failed and that preimage is the witness: a rational conic patch with base
 * points (a half cylinder of trj2_io1-ca-214) gave no solution for points on it, and a
 * transversal curve through both patches was dropped from a certified pair. */
static int keep_piece(const _cb_ssi_pair_geom *g, const sample *s)
{
    if (g->p_analytic || !g->p_pencil)
        return 1;
    cb_inversion_params par;
    cb_inversion_params_default(&par);
    par.dist_tol = 100 * g->tol;
    cb_inversion_t inv;
    cb_inversion_init(inv);
    cb_error err;
    int in = 1;
    if (cb_inversion_solve(inv, g->p_pencil, g->p, s->X, &par, &err) == CB_OK)
        in = inv->inside || (inv->n == 0 && s->in);
    cb_inversion_clear(inv);
    return in;
}

/* Appends p's point s, widening p's gap. */
static cb_status push_sample(_cb_ssi_piece *p, const sample *s)
{
    p->gap = FLINT_MAX(p->gap, s->gap);
    return _cb_ssi_piece_push(p, &s->pq, s->X);
}

/* Moves pc, built with status st, into out; when st failed or out cannot grow, pc is freed,
 * out is left as it was and the result is CB_ERR_NOMEM. */
static cb_status take_piece(_cb_ssi_piece_set *out, _cb_ssi_piece *pc, cb_status st)
{
    _cb_ssi_piece *p = st == CB_OK ? _cb_ssi_piece_set_add(out) : NULL;
    if (!p) {
        _cb_ssi_piece_clear(pc);
        return CB_ERR_NOMEM;
    }
    *p = *pc;
    return CB_OK;
}

/* The end e of a piece at a split point s on P's box (clipping): the side of a spline P's patch
 * it was refined onto (u or v held: s->pq.fixed), with an enclosure of its free parameter from
 * the refinement (ssi_tol.h CB_SSI_SPLIT_*): the crossing of that side curve C with Q lies
 * within gap / |n_Q . C'| of it to first order. Analytic P: its range's ends are face
 * boundaries (no neighbour), and the end is on no line. */
static void split_end(_cb_ssi_end *e, const sample *s, const _cb_ssi_pair_geom *g)
{
    if (g->p_analytic || !(s->pq.fixed & 3u) || (s->pq.fixed & 3u) == 3u)
        return;
    int dir = (s->pq.fixed & 2u) ? 1 : 0, fr = 1 - dir;
    double c = s->pq.uv[dir];
    if (c != 0 && c != 1)
        return;
    double P[3], Pu[3], Pv[3], Q[3], Qs[3], Qt[3], n[3];
    p_eval(P, Pu, Pv, g, s->pq.uv[0], s->pq.uv[1]);
    patch_eval(Q, Qs, Qt, g->q, s->pq.st[0], s->pq.st[1]);
    n[0] = Qs[1] * Qt[2] - Qs[2] * Qt[1];
    n[1] = Qs[2] * Qt[0] - Qs[0] * Qt[2];
    n[2] = Qs[0] * Qt[1] - Qs[1] * Qt[0];
    double ln = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double *Cp = fr ? Pv : Pu;
    double rate = ln > 0 ? fabs(n[0] * Cp[0] + n[1] * Cp[1] + n[2] * Cp[2]) / ln : 0;
    double gap = fmax(s->gap, CB_SSI_SPLIT_ROUND * g->size);
    double b = rate > 0 ? CB_SSI_SPLIT_SAFETY * gap / rate : HUGE_VAL;
    /* Q (nearly) tangent to P's side curve there: the first-order bound says nothing, and the
     * end is on no line (stitching then treats it as a free end). */
    if (!(b <= 1))
        return;
    double x = s->pq.uv[fr];
    _cb_ssi_end_add_line(e, 0, dir, c == 0 ? 1 : -1, c, x - b, x + b);
}

/* Appends S[a..b], after pre and before post, as one piece when keep_piece takes it; v0, v1:
 * the graph vertices S[a] and S[b] are (-1: none; a piece starting at a split point pre is
 * on P's side instead). CB_ERR_NOMEM leaves out as it was. */
static cb_status emit(_cb_ssi_piece_set *out, const sample *S, slong a, slong b,
                      const sample *pre, const sample *post, int closed, int tangential,
                      slong v0, slong v1, const _cb_ssi_pair_geom *g)
{
    slong mid = (a + b) / 2;
    if (!keep_piece(g, S + mid))
        return CB_OK;
    _cb_ssi_piece pc;
    _cb_ssi_piece_init(&pc);
    pc.closed = closed;
    pc.tangential = tangential;
    cb_status st = pre ? push_sample(&pc, pre) : CB_OK;
    for (slong i = a; i <= b && st == CB_OK; i++)
        st = push_sample(&pc, S + i);
    if (st == CB_OK && post)
        st = push_sample(&pc, post);
    if (!closed) {
        if (pre)
            split_end(pc.end, pre, g);
        else
            pc.end[0].vid = v0;
        if (post)
            split_end(pc.end + 1, post, g);
        else
            pc.end[1].vid = v1;
    }
    return take_piece(out, &pc, st);
}

/* Clips the parameter interval [*t0, *t1] of x(t) = a + t d to lo <= x <= hi: 0 when empty. */
static int clip_slab(double *t0, double *t1, double a, double d, double lo, double hi)
{
    if (d == 0)
        return a >= lo && a <= hi;
    double p = (lo - a) / d, q = (hi - a) / d;
    *t0 = fmax(*t0, fmin(p, q));
    *t1 = fmin(*t1, fmax(p, q));
    return *t0 <= *t1;
}

/* The straight segment between the P parameters ua and ub passes within margin times the box
 * size of P's box (Liang-Barsky). Then the two outside samples may hide an inside piece between
 * them. An angular direction is taken the short way round, in both lifts that can meet the
 * range (the one at or above its widened start and the one a period below); a range that,
 * widened, covers a whole turn does not restrict. (Untested angles made every step of a curve
 * passing beside a face's angular range count as crossing it: densified to 1e-7, seconds per
 * face pair.) */
static int seg_near_box(const _cb_ssi_pair_geom *g, const double ua[2], const double ub[2],
                        double margin)
{
    double lo[2], hi[2], a[2][2], d[2];
    int lifts[2] = {1, 1};
    for (int i = 0; i < 2; i++) {
        lo[i] = g->p_analytic ? g->an_range[2 * i] : 0;
        hi[i] = g->p_analytic ? g->an_range[2 * i + 1] : 1;
        double per = g->p_analytic ? g->an_period[i] : 0;
        if (!isfinite(lo[i]) || !isfinite(hi[i])) {
            lo[i] = -HUGE_VAL;
            hi[i] = HUGE_VAL;
        } else {
            double m = margin * (hi[i] - lo[i]);
            lo[i] -= m;
            hi[i] += m;
        }
        a[i][0] = ua[i];
        d[i] = ub[i] - ua[i];
        if (per > 0) {
            if (!(hi[i] - lo[i] < per)) {
                lo[i] = -HUGE_VAL;
                hi[i] = HUGE_VAL;
                continue;
            }
            d[i] = remainder(d[i], per);
            a[i][0] = lo[i] + fmod(fmod(ua[i] - lo[i], per) + per, per);
            a[i][1] = a[i][0] - per;
            lifts[i] = 2;
        }
    }
    for (int j = 0; j < lifts[0]; j++)
        for (int k = 0; k < lifts[1]; k++) {
            double t0 = 0, t1 = 1;
            if (clip_slab(&t0, &t1, a[0][j], d[0], lo[0], hi[0]) &&
                clip_slab(&t0, &t1, a[1][k], d[1], lo[1], hi[1]))
                return 1;
        }
    return 0;
}

/* Largest P-parameter step between consecutive samples that the densification leaves, as a
 * fraction of P's box size. */
#define DENSE_STEP 0x1p-6

/* The sample of the curve between a and b: the midpoint of their Q parameters refined onto
 * both surfaces (the traced chord is close to the curve, so it lands on the same branch).
 * Returns 1 when the refinement slid away from the chord (the sample is then not used). */
static int mid_sample(sample *m, const sample *a, const sample *b, const _cb_ssi_pair_geom *g)
{
    _cb_ssi_pq pq;
    for (int i = 0; i < 2; i++) {
        pq.st[i] = 0.5 * (a->pq.st[i] + b->pq.st[i]);
        pq.uv[i] = 0.5 * (a->pq.uv[i] + b->pq.uv[i]);
    }
    pq.fixed = a->pq.fixed & b->pq.fixed & 12u;
    double X[3];
    patch_eval(X, NULL, NULL, g->q, pq.st[0], pq.st[1]);
    if (g->p_analytic)
        analytic_invert(pq.uv, g, X, a->pq.uv);
    else
        p_project(pq.uv, g, X);
    m->gap = refine(&pq, m->X, g);
    m->pq = pq;
    m->in = inside_p(g, &pq, m->gap);
    /* The refinement moves Q's parameters too and may slide along the curve, away from the
     * chord between a and b (seen next to a rational P's seam): such a sample is not between
     * them. It must stay in the chord's box widened by half the chord's extent in its longer
     * direction, in both directions: the Newton step onto the curve is across the chord, and
     * where the chord runs nearly along one parameter line its extent in the other is next
     * to nothing (a curve running round a cylinder), so a box widened per direction would
     * call the step across it a slide and drop the piece between a and b. */
    double lo[2], hi[2], w = 0;
    for (int i = 0; i < 2; i++) {
        lo[i] = fmin(a->pq.st[i], b->pq.st[i]);
        hi[i] = fmax(a->pq.st[i], b->pq.st[i]);
        w = fmax(w, 0.5 * (hi[i] - lo[i]));
    }
    w += 1e-12;
    int slid = 0;
    for (int i = 0; i < 2; i++)
        slid |= !(pq.st[i] >= lo[i] - w && pq.st[i] <= hi[i] + w);
    return slid;
}

/* Appends to D the samples strictly between a and b needed so that no inside piece hides
 * between two outside samples: while both are outside and their P-parameter segment comes
 * within a quarter of P's box size of the box and is longer than DENSE_STEP of it, or crosses
 * the box itself and is longer than 1e-7 of it, the midpoint is inserted (depth <= 40).
 * CB_ERR_NOMEM leaves D holding the samples appended so far. */
static cb_status densify(sample **D, slong *nd, slong *alloc, const sample *a, const sample *b,
                         const _cb_ssi_pair_geom *g, int depth)
{
    if (depth >= 40 || a->in || b->in || !seg_near_box(g, a->pq.uv, b->pq.uv, 0.25))
        return CB_OK;
    double step = seg_near_box(g, a->pq.uv, b->pq.uv, 0) ? 1e-7 : DENSE_STEP;
    double len = 0;
    for (int i = 0; i < 2; i++) {
        double w = g->p_analytic ? g->an_range[2 * i + 1] - g->an_range[2 * i] : 1;
        if (g->p_analytic && (g->an_period[i] > 0 || !isfinite(w)))
            continue;
        len = fmax(len, fabs(b->pq.uv[i] - a->pq.uv[i]) / w);
    }
    if (len <= step)
        return CB_OK;
    sample m;
    if (mid_sample(&m, a, b, g))
        return CB_OK; /* no sample to be had between them: as if none were needed */
    if (densify(D, nd, alloc, a, &m, g, depth + 1) != CB_OK)
        return CB_ERR_NOMEM;
    if (*nd == *alloc) {
        sample *q = realloc(*D, (size_t)(2 * *alloc) * sizeof(sample));
        if (!q)
            return CB_ERR_NOMEM;
        *D = q;
        *alloc *= 2;
    }
    (*D)[(*nd)++] = m;
    return densify(D, nd, alloc, &m, b, g, depth + 1);
}

/* Whether X lies within 10 tol of the box of P's control points (which holds P's patch). */
static int near_net(const _cb_ssi_pair_geom *g, const double X[3])
{
    double slack = 10 * g->tol;
    for (int k = 0; k < 3; k++)
        if (!(X[k] >= g->p_net.lo[k] - slack && X[k] <= g->p_net.hi[k] + slack))
            return 0;
    return 1;
}

/* Sample i of the traced curve: P's parameters continued from the neighbouring sample prev
 * (a fresh inversion when there is none, or it lies off the surfaces), refined onto both
 * surfaces, and whether it lies inside P's box. */
static void place_sample(sample *S, const sample *prev, const _cb_ssi_trace_curve *tc, slong i,
                         const _cb_ssi_pair_geom *g, int p_spline)
{
    double X[3];
    patch_eval(X, NULL, NULL, g->q, tc->st[2 * i], tc->st[2 * i + 1]);
    _cb_ssi_pq pq = {{0, 0}, {tc->st[2 * i], tc->st[2 * i + 1]}, tc->fixed[i]};
    int started = !prev || !(prev->gap <= 10 * g->tol);
    if (started)
        p_start(pq.uv, g, X);
    else if (g->p_analytic)
        analytic_invert(pq.uv, g, X, prev->pq.uv);
    else {
        memcpy(pq.uv, prev->pq.uv, sizeof pq.uv);
        p_project(pq.uv, g, X);
    }
    S->gap = refine(&pq, S->X, g);
    S->pq = pq;
    S->in = inside_p(g, &pq, S->gap);
    /* A patch's parameterisation continued past its box may cover its surface again (a
     * rational quarter circle's extends to the whole circle; a polynomial patch folds, a
     * planar one back over its plane): followed from one preimage, the parameters may reach a
     * point of the patch by another, outside the box. A fresh start prefers one inside: for a
     * curved spline the Dixon inversion, which finds every preimage, where it may have one
     * inside (p_may_hold: a start from an outside preimage is no better founded than the
     * continuation, and these inversions of points far from the patch were half the clipping
     * time); for a planar patch (no pencil) the grid over the box, for points within the box
     * of its control points, which holds the patch (trj5 against its copy: a line through a
     * flat wall and a planar span of a closed strip, the piece inside both once dropped from
     * a certified pair). */
    if (!S->in && !started && !g->p_analytic &&
        (p_spline ? p_may_hold(g, X) : near_net(g, X))) {
        _cb_ssi_pq alt = {{0, 0}, {tc->st[2 * i], tc->st[2 * i + 1]}, tc->fixed[i]};
        double Xa[3];
        p_start(alt.uv, g, X);
        double gap = refine(&alt, Xa, g);
        if (inside_p(g, &alt, gap)) {
            S->pq = alt;
            S->gap = gap;
            memcpy(S->X, Xa, sizeof Xa);
            S->in = 1;
        }
    }
}

/* One traced curve of _cb_ssi_clip: its pieces appended to out. */
static cb_status clip_curve(_cb_ssi_piece_set *out, const _cb_ssi_trace_curve *tc,
                            const _cb_ssi_pair_geom *g)
{
    slong n = tc->n;
    if (n == 0)
        return CB_OK;
    sample *S = malloc((size_t)(n + 1) * sizeof(sample));
    if (!S)
        return CB_ERR_NOMEM;
    /* A curved spline P (with a Dixon pencil) may cover a point by several preimages; a
     * planar one (no pencil) keeps the preimages its continuation finds (re-placing them cost
     * trj5's plane against rod pairs 25 s each, densified to 1e-7 between sheets). */
    int p_spline = !g->p_analytic && g->p_pencil;
    /* For a curved spline P, samples are placed from the middle of the curve outwards, each
     * continued from its neighbour towards the middle: an end may be a node where the curve
     * crosses P's self-intersection (the paper's Example 2), whose preimages on both sheets
     * lie inside the box; continued from the curve's inside, it gets the preimage of its own
     * sheet. Otherwise from the first sample on. */
    slong mid = p_spline ? n / 2 : 0;
    place_sample(S + mid, NULL, tc, mid, g, p_spline);
    for (slong i = mid - 1; i >= 0; i--)
        place_sample(S + i, S + i + 1, tc, i, g, p_spline);
    for (slong i = mid + 1; i < n; i++)
        place_sample(S + i, S + i - 1, tc, i, g, p_spline);
    /* The point where the curve leaves the box is sought between an inside sample and its
     * outside neighbour, along their parameters: both must be on one sheet. An outside
     * neighbour is placed again from the inside sample's parameters (on a planar P too: an
     * inside sample may have been placed from the grid, place_sample). */
    for (slong i = 0; !g->p_analytic && i < n; i++)
        for (int side = -1; side <= 1 && S[i].in; side += 2) {
            slong j = i + side;
            if (j < 0 || j >= n || S[j].in)
                continue;
            _cb_ssi_pq pq = {{S[i].pq.uv[0], S[i].pq.uv[1]},
                             {tc->st[2 * j], tc->st[2 * j + 1]},
                             tc->fixed[j]};
            double X[3], Xr[3];
            patch_eval(X, NULL, NULL, g->q, tc->st[2 * j], tc->st[2 * j + 1]);
            p_project(pq.uv, g, X);
            double gap = refine(&pq, Xr, g);
            if (gap <= 10 * g->tol && !inside_p(g, &pq, gap)) {
                S[j].pq = pq;
                S[j].gap = gap;
                memcpy(S[j].X, Xr, sizeof Xr);
            }
        }
    if (!tc->isolated && n > 1) {
        /* A long traced chord between two outside samples (a straight line needs few) may
         * cross P's box: sample it there. */
        slong nd = 0, alloc = 2 * n + 2;
        sample *D = malloc((size_t)alloc * sizeof(sample));
        cb_status st = D ? CB_OK : CB_ERR_NOMEM;
        for (slong i = 0; i < n && st == CB_OK; i++) {
            if (i > 0)
                st = densify(&D, &nd, &alloc, S + i - 1, S + i, g, 0);
            if (st == CB_OK && nd + 1 >= alloc) {
                sample *q = realloc(D, (size_t)(2 * alloc) * sizeof(sample));
                if (q) {
                    D = q;
                    alloc *= 2;
                } else {
                    st = CB_ERR_NOMEM;
                }
            }
            if (st == CB_OK)
                D[nd++] = S[i];
        }
        free(S);
        if (st != CB_OK) {
            free(D);
            return st;
        }
        S = D;
        n = nd;
    }
    if (tc->isolated) {
        cb_status st = CB_OK;
        if (S[0].in && keep_piece(g, S)) {
            _cb_ssi_piece pc;
            _cb_ssi_piece_init(&pc);
            pc.isolated = pc.tangential = 1;
            pc.end[0].vid = tc->v[0];
            st = take_piece(out, &pc, push_sample(&pc, S));
        }
        free(S);
        return st;
    }
    slong all_in = 1;
    for (slong i = 0; i < n; i++)
        all_in &= S[i].in;
    if (all_in) {
        cb_status st = emit(out, S, 0, n - 1, NULL, NULL, tc->closed, tc->tangential,
                            tc->closed ? -1 : tc->v[0], tc->closed ? -1 : tc->v[1], g);
        free(S);
        return st;
    }
    if (tc->closed) {
        /* Rotate the loop (its last point repeats the first) to start outside. */
        slong k = 0;
        while (S[k].in)
            k++;
        sample *R = malloc((size_t)n * sizeof(sample));
        if (!R) {
            free(S);
            return CB_ERR_NOMEM;
        }
        for (slong i = 0; i < n - 1; i++)
            R[i] = S[(k + i) % (n - 1)];
        R[n - 1] = R[0];
        free(S);
        S = R;
    }
    cb_status st = CB_OK;
    for (slong i = 0; i < n && st == CB_OK;) {
        if (!S[i].in) {
            i++;
            continue;
        }
        slong j = i;
        while (j + 1 < n && S[j + 1].in)
            j++;
        sample pre, post;
        if (i > 0)
            split_point(&pre.pq, pre.X, &pre.gap, g, &S[i].pq, S[i].X, S[i].gap, &S[i - 1].pq);
        if (j + 1 < n)
            split_point(&post.pq, post.X, &post.gap, g, &S[j].pq, S[j].X, S[j].gap,
                        &S[j + 1].pq);
        /* Ends at the traced curve's own ends are its graph vertices (a loop has none: it
         * was rotated to start outside). */
        slong v0 = !tc->closed && i == 0 ? tc->v[0] : -1;
        slong v1 = !tc->closed && j == n - 1 ? tc->v[1] : -1;
        st = emit(out, S, i, j, i > 0 ? &pre : NULL, j + 1 < n ? &post : NULL, 0, tc->tangential,
                  v0, v1, g);
        i = j + 1;
    }
    free(S);
    return st;
}

cb_status _cb_ssi_clip(_cb_ssi_piece_set *out, const _cb_ssi_trace_set *ts,
                       const _cb_ssi_pair_geom *g)
{
    cb_status st = CB_OK;
    for (slong c = 0; c < ts->n && st == CB_OK; c++)
        st = clip_curve(out, ts->c + c, g);
    return st;
}
